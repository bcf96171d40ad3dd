"""Test vectors of the dead-time compensation (golden/fpga/deadtime_comp.py compensate), shared by
cocotb_tests/tb_deadtime_comp.py and tests/test_hls_deadtime_comp.py.

A vector is a dict of the ``HELD`` registers and the ``SAMPLED`` inputs (the hfi_deadtime_comp port
names; ``sign_top`` 1 = falling half, sign +1). :func:`draw`: the modulator's register draws with a
random sign and compares in 0..H (extremes 0, 1, H/2, H-1, H included); :func:`corner_vectors`: register
extremes; :func:`saturation_vectors`: leg a's predicted current around the RTL's saturation bound.
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr
from golden.fpga.deadtime_comp import phase_current, recip_half
from golden.testvectors.modulator import U32, draw_registers

HELD = ("half", "dead", "gain", "i_d_ref", "i_q_ref", "hf_amp", "sin_q15", "cos_q15", "recip_h")
SAMPLED = ("sign_top", "cmp_a_in", "cmp_b_in", "cmp_c_in")


def draw(rng, n: int) -> list[dict]:
    """Random inputs: the modulator's register draws, a sign and compares in 0..H."""
    reg = draw_registers(rng, n)
    r = {"half": reg["half"], "dead": reg["dead"], "gain": reg["dtc_gain"], "i_d_ref": reg["i_d_ref"],
         "i_q_ref": reg["i_q_ref"], "hf_amp": reg["hf_amp"], "sin_q15": reg["sin_q15"],
         "cos_q15": reg["cos_q15"], "recip_h": reg["recip_h"], "sign_top": rng.integers(0, 2, n)}
    h = r["half"]
    for name in ("cmp_a_in", "cmp_b_in", "cmp_c_in"):
        x = (rng.random(n) * (h + 1)).astype(np.int64)
        ext = np.stack([np.zeros(n, np.int64), np.ones(n, np.int64), h // 2, h - 1, h])
        pick = rng.integers(0, 5, n)
        r[name] = np.where(rng.random(n) < 0.2, ext[pick, np.arange(n)], x)
    names = HELD + SAMPLED
    cols = [r[k].tolist() for k in names]
    return [dict(zip(names, vals)) for vals in zip(*cols)]


def corner_vectors(rng: np.random.Generator) -> list[dict]:
    """Extremes: compares 0 / H, full-scale currents and angles, RECIP_H 0 / 2^32-1, D 1 / 65535, gain
    1 / 65535, both signs; and DTC_GAIN = 0 (identity). ``rng`` picks the reference currents of a third."""
    vecs = []
    for half in (512, 65534):
        for s, c in ((-32768, -32768), (32767, 32767), (0, -32768), (-32768, 0), (23170, -23170)):
            for rh in (recip_half(half), U32, 0):
                for gain, dead in ((65535, 65535), (1, 1), (65535, 1), (256, 40), (0, 400)):
                    for sign in (0, 1):
                        for cmps in ((0, half, half // 2), (half, 0, 1)):
                            vecs.append(dict(half=half, dead=dead, gain=gain, i_d_ref=-32768, i_q_ref=32767,
                                             hf_amp=32767, sin_q15=s, cos_q15=c, recip_h=rh, sign_top=sign,
                                             cmp_a_in=cmps[0], cmp_b_in=cmps[1], cmp_c_in=cmps[2]))
    for r in vecs[1::3]:                                 # other reference currents
        r["i_d_ref"], r["i_q_ref"] = (int(v) for v in rng.choice([-32768, 32767, 0, 1, -1], 2))
    return vecs


def saturation_vectors() -> list[dict]:
    """Leg a's predicted current i_x placed exactly on values around +-2^23 and +-2^24 (the RTL
    saturates i_x to +-(2^24 - 1) before the gain product), with small gains and large D, so that c
    depends on every bit of i_x up to the clamp; RECIP_H sets the HF term (hf ~ -i_x), I_D_REF the
    exact value. Top sign with cmp_a = 0 for positive i_x, bottom sign with cmp_a = H for negative."""
    H = 65534
    out = []
    for t in (2**23 - 1, 2**23, 2**23 + 1, 3 * 2**22, 2**24 - 600, 2**24 - 257, 2**24 - 256,
              2**24 - 255, 2**24 - 2, 2**24 - 1, 2**24, 2**24 + 1, 2**25, 2**31 - 2**20):
        for target in (t, -t):
            top = target > 0
            cmp_a = 0 if top else H
            d = 2 * cmp_a - H                                   # -H (top) or +H (bottom)
            i_d = round(target * 32768 / 32767)                 # i_al = round_shr(i_d*32767, 15)
            rh = min(U32, max(0, round(-i_d * 2**32 / (32767 * d))))
            hf = round_shr(32767 * d * rh, 32)
            base = dict(half=H, dead=65535, gain=1, i_d_ref=0, i_q_ref=0, hf_amp=32767, sin_q15=0,
                        cos_q15=32767, recip_h=rh, sign_top=int(top), cmp_a_in=cmp_a,
                        cmp_b_in=H // 2, cmp_c_in=H // 2)
            best = None
            for idr in range(max(-32768, i_d + hf - 40), min(32767, i_d + hf + 40) + 1):
                ix = phase_current(0, idr - hf, 0, 0, 32767)
                if best is None or abs(ix - target) < abs(best[1] - target):
                    best = (idr, ix)
            base["i_d_ref"] = best[0]
            for gain, dead in ((1, 65535), (2, 65535), (255, 65535), (256, 40000), (1, 40000)):
                out.append(base | dict(gain=gain, dead=dead))
    return out
