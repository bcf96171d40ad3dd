"""The optional hardware blocks of an FPGA build (docs/rtl.md "Build options").

Each is a Verilog parameter of the same name (``hfi_dsp``: ROT_INJ, DIFF_CIC, FCS_MPC; ``hfi_soc_acc``: FLUX_LUT;
all passed through ``hfi_soc``), 1 by default, and a bit of the read-only CAPS register of its register map
(rtl/regs/hfi_regs.rdl, rtl/regs/hfi_acc.rdl: the one source of the names and bits). A method names the options
it needs in its ``MethodInfo.hardware`` (golden.firmware.estimator); the firmware compares them with CAPS before
it starts the drive, and ``hfi compare`` synthesizes each system with only its own options.
"""

from __future__ import annotations

from golden import accmap, regmap

DSP_OPTIONS: tuple[str, ...] = tuple(regmap.REGISTERS["CAPS"]["fields"])
"""Options of hfi_dsp, in CAPS bit order."""
ACC_OPTIONS: tuple[str, ...] = tuple(accmap.REGISTERS["CAPS"]["fields"])
"""Options of hfi_soc_acc (the accelerators; a build without them, ACC = 0, needs none)."""
OPTIONS: tuple[str, ...] = DSP_OPTIONS + ACC_OPTIONS


def caps_masks(names) -> tuple[int, int]:
    """(hfi_regs CAPS mask, hfi_acc CAPS mask) of the options ``names``; ValueError names an unknown one."""
    dsp = acc = 0
    for name in names:
        if name in DSP_OPTIONS:
            dsp |= 1 << regmap.REGISTERS["CAPS"]["fields"][name][0]
        elif name in ACC_OPTIONS:
            acc |= 1 << accmap.REGISTERS["CAPS"]["fields"][name][0]
        else:
            raise ValueError(f"unknown build option {name!r} (known: {', '.join(OPTIONS)})")
    return dsp, acc


def needed(low: str, high: str) -> tuple[str, ...]:
    """The options the estimator methods ``low`` and ``high`` (scenario names, ``estimator.low`` / ``.high``) need,
    in :data:`OPTIONS` order: the system a scenario describes (``hfi compare`` synthesizes it, the rtl backend
    simulates it). An unknown name needs none (the scenario's own check names it)."""
    from golden.firmware.estimator import METHODS

    need = {o for name in (low, high) if name in METHODS for o in METHODS[name].hardware}
    return tuple(o for o in OPTIONS if o in need)


def left_out(low: str, high: str) -> dict[str, int]:
    """The build options the methods ``low`` and ``high`` do not need, each 0: the parameters of their system's build
    (every other option keeps its default, 1)."""
    need = needed(low, high)
    return {o: 0 for o in OPTIONS if o not in need}
