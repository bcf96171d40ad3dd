// Sample differencing, envelope and CIC interpolation: docs/spec.md 3.9, golden.fpga.diff_cic (DiffCic);
// Xue et al. 2022, eq. (7) (the difference of successive carrier-bottom samples) and eq. (8) (the CIC
// interpolator, in the comb-then-integrator form of Fig. 8).
#include "hfi_diff_cic.h"

void hfi_diff_cic_reset(hfi_diff_cic_state &st) {
#pragma HLS INLINE
    st.valid = false;
    st.m = 0;
    for (int k = 0; k < 2; k++) {
#pragma HLS UNROLL
        st.p[k] = 0;
        st.e[k] = 0;
        st.y[k] = 0;
        for (int j = 0; j < HFI_CIC_M_MAX; j++) {
#pragma HLS UNROLL
            st.x[k][j] = 0;
        }
    }
}

// golden.fpga.diff_cic.cic_m: min(max(reg, 1), M_MAX).
ap_uint<5> hfi_cic_m(ap_uint<8> cic_m_reg) {
#pragma HLS INLINE
    return cic_m_reg == 0 ? ap_uint<5>(1)
                          : (cic_m_reg > HFI_CIC_M_MAX ? ap_uint<5>(HFI_CIC_M_MAX) : ap_uint<5>(cic_m_reg));
}

// DiffCic.step: 1. a change of the clamped M clears x and y; per component 2., 3. e = i - p if a previous
// sample exists and plus, else e holds, p = i; 4. c = e - x[M-1] (s18), x shifts in e, y = wrap(y + c, 21)
// (the s22 sum truncated to s21: the two's-complement wrap; y stays the exact sum of the last M values,
// which lies in s21).
void hfi_diff_cic_step(hfi_diff_cic_state &st, s16 i_alpha, s16 i_beta, bool plus, ap_uint<8> cic_m,
                       s21 &q_a, s21 &q_b, s17 &e_a, s17 &e_b) {
#pragma HLS INLINE off
#pragma HLS ARRAY_PARTITION variable = st.p complete
#pragma HLS ARRAY_PARTITION variable = st.e complete
#pragma HLS ARRAY_PARTITION variable = st.y complete
#pragma HLS ARRAY_PARTITION variable = st.x complete dim = 0
    const ap_uint<5> m = hfi_cic_m(cic_m);
    const bool restart = m != st.m;
    st.m = m;
    const s16 i[2] = {i_alpha, i_beta};
#pragma HLS ARRAY_PARTITION variable = i complete
    for (int k = 0; k < 2; k++) {
#pragma HLS UNROLL
        if (st.valid && plus)
            st.e[k] = s17(i[k] - st.p[k]);
        st.p[k] = i[k];
        if (restart) {
            st.y[k] = 0;
            for (int j = 0; j < HFI_CIC_M_MAX; j++) {
#pragma HLS UNROLL
                st.x[k][j] = 0;
            }
        }
        const ap_int<18> c = st.e[k] - st.x[k][m - 1];
        for (int j = HFI_CIC_M_MAX - 1; j > 0; j--) {
#pragma HLS UNROLL
            st.x[k][j] = st.x[k][j - 1];
        }
        st.x[k][0] = st.e[k];
        st.y[k] = s21(st.y[k] + c);
    }
    st.valid = true;
    q_a = st.y[0];
    q_b = st.y[1];
    e_a = st.e[0];
    e_b = st.e[1];
}
