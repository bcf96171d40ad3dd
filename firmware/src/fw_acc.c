/* fw_acc.c - the SoC build's sine/cosine, vector angle and flux-map look-up: the arithmetic accelerators of
 * hfi_soc_acc (rtl/hfi_soc_acc.v, docs/acc_registers.md, docs/soc.md "Accelerators"). Each computes the same
 * function as control.c's software version (golden.fpga.cordic.sincos_q15 with 32 bits and 16 iterations,
 * golden.firmware.vector.vector_angle, golden.firmware.flux_lut.lut_point), bit for bit
 * (cocotb_tests/test_soc_acc.py, test_vector.py, test_flux_lut.py); the
 * host build (tests/test_fw_c.py) keeps the software, the SoC build (-DFW_ACC) links this file instead.
 * An access that needs a result is answered when it is ready (a SINCOS read, the LUT_IQ write): no polling. */

#include <stdint.h>

#include "control.h"
#include "hfi_acc_regs.h"
#include "hfi_soc_platform.h"

#define ACC(reg) (*(volatile uint32_t *)(HFI_SOC_ACC_BASE + HFI_ACC__##reg##_offset))
#define ACC_FIELD(reg, fld, v) (((uint32_t)(v) << HFI_ACC__##reg##__##fld##_bp) & HFI_ACC__##reg##__##fld##_bm)

/* CAPS of the accelerators: the optional units of this build (golden.build_options) */
uint32_t fw_acc_caps(void)
{
    return ACC(CAPS);
}

/* golden.fpga.cordic.sincos_q15(angle, 32, 16) */
void fw_sincos_q15(uint32_t angle, int32_t *sin_q15, int32_t *cos_q15)
{
    ACC(SIN_ANGLE) = angle;
    uint32_t v = ACC(SINCOS);

    *sin_q15 = (int16_t)((v & HFI_ACC__SINCOS__SIN_bm) >> HFI_ACC__SINCOS__SIN_bp);
    *cos_q15 = (int16_t)((v & HFI_ACC__SINCOS__COS_bm) >> HFI_ACC__SINCOS__COS_bp);
}

/* fw_sincos_q15 in two halves: the write starts the CORDIC, the read waits for it (control.h) */
void fw_sincos_start(uint32_t angle)
{
    ACC(SIN_ANGLE) = angle;
}

void fw_sincos_take(int32_t *sin_q15, int32_t *cos_q15)
{
    uint32_t v = ACC(SINCOS);

    *sin_q15 = (int16_t)((v & HFI_ACC__SINCOS__SIN_bm) >> HFI_ACC__SINCOS__SIN_bp);
    *cos_q15 = (int16_t)((v & HFI_ACC__SINCOS__COS_bm) >> HFI_ACC__SINCOS__COS_bp);
}

/* golden.firmware.vector.vector_angle(x, y); the callers keep |x|, |y| <= 2^28 (the unit saturates to it) */
void fw_vector_angle(int32_t x, int32_t y, uint32_t *angle, int32_t *mag)
{
    ACC(VEC_X) = (uint32_t)x;
    ACC(VEC_Y) = (uint32_t)y;                          /* starts the vectoring CORDIC */
    *angle = ACC(VEC_ANGLE);                           /* waits for it */
    *mag = (int32_t)ACC(VEC_MAG);
}

/* The unit reads the tables from the RAM, where the configuration block holds them: the grid and the
 * tables' addresses are written when a look-up names a table other than the last one (the configuration
 * block is written once before the firmware starts, so a table's address names its contents). */
/* in .state_vars (firmware/link.ld): read every 003 step, its data-cache line must not move with the code's size (in
 * .bss, after the code and the constants, it once landed on the step's stack frames' line: 2 refills per period) */
static const struct fw_flux_lut *acc_lut __attribute__((section(".state_vars")));

static void acc_lookup(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q)
{
    if (lut != acc_lut) {
        ACC(LUT_CFG) = ACC_FIELD(LUT_CFG, N_D, lut->n_d) | ACC_FIELD(LUT_CFG, N_Q, lut->n_q)
                       | ACC_FIELD(LUT_CFG, SHIFT, lut->shift) | ACC_FIELD(LUT_CFG, COARSE, lut->coarse)
                       | ACC_FIELD(LUT_CFG, F_SHIFT, lut->f_shift);
        ACC(LUT_KNEE) = (uint32_t)lut->knee;
        ACC(LUT_BASE_D) = (uint32_t)(uintptr_t)lut->t_d;
        ACC(LUT_BASE_Q) = (uint32_t)(uintptr_t)lut->t_q;
        ACC(LUT_BASE_LD) = (uint32_t)(uintptr_t)lut->t_ld;
        ACC(LUT_BASE_LQ) = (uint32_t)(uintptr_t)lut->t_lq;
        ACC(LUT_BASE_LDQ) = (uint32_t)(uintptr_t)lut->t_ldq;
        acc_lut = lut;
    }
    ACC(LUT_ID) = (uint32_t)i_d;
    ACC(LUT_IQ) = (uint32_t)i_q;                     /* starts the look-up, answered when it is done */
}

#define ACC64(reg) ((int64_t)(((uint64_t)ACC(reg##_HI) << 32) | ACC(reg##_LO)))

/* golden.firmware.flux_lut.lut_flux */
void fw_lut_flux(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, int64_t *lam_d, int64_t *lam_q)
{
    acc_lookup(lut, i_d, i_q);
    *lam_d = ACC64(LAM_D);
    *lam_q = ACC64(LAM_Q);
}

/* golden.firmware.flux_lut.lut_point */
void fw_lut_point(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, struct fw_lut_point *pt)
{
    acc_lookup(lut, i_d, i_q);
    pt->lam_d = ACC64(LAM_D);
    pt->lam_q = ACC64(LAM_Q);
    pt->l_d = (int32_t)ACC(L_D);
    pt->l_q = (int32_t)ACC(L_Q);
    pt->l_dq = (int32_t)ACC(L_DQ);
    pt->dl_d = ACC64(DL_D);
    pt->dl_q = ACC64(DL_Q);
    pt->dl_dq = ACC64(DL_DQ);
}
