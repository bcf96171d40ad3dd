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
