/* fw_acc.c - the SoC build's sine/cosine and flux-map look-up: the arithmetic accelerators of hfi_soc_acc
 * (rtl/hfi_soc_acc.v, docs/acc_registers.md, docs/soc.md "Accelerators"). Each computes the same function
 * as control.c's software version (golden.fpga.cordic.sincos_q15 with 32 bits and 16 iterations,
 * golden.firmware.flux_lut.lut_point), bit for bit (cocotb_tests/test_soc_acc.py, test_flux_lut.py); the
 * host build (tests/test_fw_c.py) keeps the software, the SoC build (-DFW_ACC) links this file instead.
 * A result register read while its unit computes is answered when the result is ready: no polling. */

#include <stdint.h>

#include "control.h"
#include "hfi_acc_regs.h"
#include "hfi_soc_platform.h"

#define ACC(reg) (*(volatile uint32_t *)(HFI_SOC_ACC_BASE + HFI_ACC__##reg##_offset))
#define ACC_FIELD(reg, fld, v) (((uint32_t)(v) << HFI_ACC__##reg##__##fld##_bp) & HFI_ACC__##reg##__##fld##_bm)

/* golden.fpga.cordic.sincos_q15(angle, 32, 16) */
void fw_sincos_q15(uint32_t angle, int32_t *sin_q15, int32_t *cos_q15)
{
    ACC(SIN_ANGLE) = angle;
    uint32_t v = ACC(SINCOS);

    *sin_q15 = (int16_t)((v & HFI_ACC__SINCOS__SIN_bm) >> HFI_ACC__SINCOS__SIN_bp);
    *cos_q15 = (int16_t)((v & HFI_ACC__SINCOS__COS_bm) >> HFI_ACC__SINCOS__COS_bp);
}

/* The table in the unit: loaded on the first look-up with a table (the warm-up step before the window
 * interrupt is enabled, main.c), again if a look-up names another one. The configuration block is written
 * once before the firmware starts, so a table's address names its contents. */
static const struct fw_flux_lut *acc_lut;

static void acc_table(int32_t table, const int32_t *t32, const int16_t *t16, int32_t n)
{
    ACC(LUT_TW_ADDR) = ACC_FIELD(LUT_TW_ADDR, TABLE, table);
    for (int32_t i = 0; i < n; i++)
        ACC(LUT_TW_DATA) = t16 ? (uint32_t)(int32_t)t16[i] : (uint32_t)t32[i];
}

static void acc_lookup(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q)
{
    if (lut != acc_lut) {
        int32_t n = lut->n_d * lut->n_q;

        ACC(LUT_CFG) = ACC_FIELD(LUT_CFG, N_D, lut->n_d) | ACC_FIELD(LUT_CFG, N_Q, lut->n_q)
                       | ACC_FIELD(LUT_CFG, SHIFT, lut->shift) | ACC_FIELD(LUT_CFG, COARSE, lut->coarse)
                       | ACC_FIELD(LUT_CFG, F_SHIFT, lut->f_shift);
        ACC(LUT_KNEE) = (uint32_t)lut->knee;
        acc_table(0, 0, lut->t_d, n);
        acc_table(1, 0, lut->t_q, n);
        acc_table(2, lut->t_ld, 0, n);
        acc_table(3, lut->t_lq, 0, n);
        acc_table(4, lut->t_ldq, 0, n);
        acc_lut = lut;
    }
    ACC(LUT_ID) = (uint32_t)i_d;
    ACC(LUT_IQ) = (uint32_t)i_q;                     /* starts the look-up */
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
