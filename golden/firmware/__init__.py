"""Firmware golden model (docs/spec.md, section 5): the per-PWM-period arithmetic of the RISC-V firmware.

Each module holds one block of the firmware as plain-int Python that the C on RV32IM (GCC) reproduces
bit for bit with ``int32_t``/``uint32_t``/``int64_t`` and the helpers of :mod:`golden.fixed` only:

* :mod:`.means`    -- per-window means of the demodulator sums (``c_div``);
* :mod:`.bangbang` -- the bang-bang angle estimator of Benevieri et al. 2023 (Sec. II-B, Fig. 1);
* :mod:`.pll`      -- the type-2 PLL that smooths the bang-bang angle and yields the speed;
* :mod:`.lowpass`  -- the first-order speed filter;
* :mod:`.pi`       -- the PI controller with conditional-integration anti-windup (speed and currents).

The docstring of every step function states the C types and the order of operations the C must use.
The ``*_raw``/``*_gains``/``*_coef`` helpers run once on the host (floats allowed there only) and
produce the integer configuration constants with :func:`golden.fixed.to_fixed`.
The step functions do not validate their arguments (they run once per PWM period in the closed loop);
the host-side helpers and :class:`.pi.PiParams` do.
"""
