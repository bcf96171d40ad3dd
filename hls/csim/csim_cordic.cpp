// C-ABI wrappers of the CORDIC kernels over arrays (tests/test_hls_cordic.py).
#include "csim_cordic.h"
#include "hfi_cordic.h"

namespace {

typedef void (*sincos_run)(int n, const uint32_t *angle, int32_t *sin_raw, int32_t *cos_raw,
                           int16_t *sin_q15, int16_t *cos_q15);
typedef void (*q15_run)(int n, const int32_t *v, int16_t *q15);

template <int WIDTH, int ITERATIONS>
void run_sincos(int n, const uint32_t *angle, int32_t *sin_raw, int32_t *cos_raw, int16_t *sin_q15,
                int16_t *cos_q15) {
    for (int k = 0; k < n; k++) {
        ap_int<WIDTH> s, c;
        hfi_cordic_sincos<WIDTH, ITERATIONS>(angle[k], s, c);
        sin_raw[k] = s.to_int();
        cos_raw[k] = c.to_int();
        sin_q15[k] = hfi_to_q15<WIDTH>(s).to_int();
        cos_q15[k] = hfi_to_q15<WIDTH>(c).to_int();
    }
}

template <int WIDTH>
void run_q15(int n, const int32_t *v, int16_t *q15) {
    for (int k = 0; k < n; k++)
        q15[k] = hfi_to_q15<WIDTH>(ap_int<WIDTH>(v[k])).to_int();
}

struct Point {
    int width, iterations;
    sincos_run run;
};

// The (WIDTH, ITERATIONS) points of the RTL tests (cocotb_tests/test_cordic.py: {17, 18, 24, 32} x
// {1, 8, 16, WIDTH}, which holds the Icarus points (32, 32), (17, 17), (24, 8)).
const Point POINTS[] = {
    {17, 1, run_sincos<17, 1>},  {17, 8, run_sincos<17, 8>},  {17, 16, run_sincos<17, 16>},
    {17, 17, run_sincos<17, 17>}, {18, 1, run_sincos<18, 1>},  {18, 8, run_sincos<18, 8>},
    {18, 16, run_sincos<18, 16>}, {18, 18, run_sincos<18, 18>}, {24, 1, run_sincos<24, 1>},
    {24, 8, run_sincos<24, 8>},  {24, 16, run_sincos<24, 16>}, {24, 24, run_sincos<24, 24>},
    {32, 1, run_sincos<32, 1>},  {32, 8, run_sincos<32, 8>},  {32, 16, run_sincos<32, 16>},
    {32, 32, run_sincos<32, 32>},
};
const int N_POINTS = sizeof(POINTS) / sizeof(POINTS[0]);

// hfi_to_q15<WIDTH> for WIDTH = 17..32, indexed by WIDTH - 17.
const q15_run Q15[] = {
    run_q15<17>, run_q15<18>, run_q15<19>, run_q15<20>, run_q15<21>, run_q15<22>, run_q15<23>, run_q15<24>,
    run_q15<25>, run_q15<26>, run_q15<27>, run_q15<28>, run_q15<29>, run_q15<30>, run_q15<31>, run_q15<32>,
};

}  // namespace

extern "C" int csim_cordic_sincos(int width, int iterations, int n, const uint32_t *angle, int32_t *sin_raw,
                                  int32_t *cos_raw, int16_t *sin_q15, int16_t *cos_q15) {
    for (int p = 0; p < N_POINTS; p++) {
        if (POINTS[p].width == width && POINTS[p].iterations == iterations) {
            POINTS[p].run(n, angle, sin_raw, cos_raw, sin_q15, cos_q15);
            return 0;
        }
    }
    return -1;
}

extern "C" int csim_cordic_points(int max, int *width, int *iterations) {
    for (int p = 0; p < N_POINTS && p < max; p++) {
        width[p] = POINTS[p].width;
        iterations[p] = POINTS[p].iterations;
    }
    return N_POINTS;
}

extern "C" int csim_cordic_to_q15(int width, int n, const int32_t *v, int16_t *q15) {
    if (width < HFI_CORDIC_WIDTH_MIN || width > HFI_CORDIC_WIDTH_MAX)
        return -1;
    Q15[width - HFI_CORDIC_WIDTH_MIN](n, v, q15);
    return 0;
}

extern "C" void csim_cordic_sincos_q15(int n, const uint32_t *angle, int16_t *sin_q15, int16_t *cos_q15) {
    for (int k = 0; k < n; k++) {
        s16 s, c;
        hfi_sincos_q15(angle[k], s, c);
        sin_q15[k] = s.to_int();
        cos_q15[k] = c.to_int();
    }
}

extern "C" void csim_cordic_demod_weight(int n, const uint16_t *counter, const uint16_t *half,
                                         const uint32_t *step, int16_t *w) {
    for (int k = 0; k < n; k++)
        w[k] = hfi_demod_weight(counter[k], half[k], step[k]).to_int();
}
