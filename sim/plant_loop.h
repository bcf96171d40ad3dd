// plant_loop.h - the window sequencing around the C plant, shared by the closed-loop backends rtl
// (sim/soc_sim.cpp, the Verilated SoC drives the plant clock by clock) and hls (hls/backend/hls_loop.cpp,
// the kernels drive it window by window). Both make the golden loop's plant calls (golden/closedloop.py)
// through this class, so the calls, the records and the error messages are written once.
//
// Window k covers the ticks [k*P + H/2, (k+1)*P + H/2) (docs/spec.md 2.1). A backend applies the gate
// edges and takes the samples of a window (per event: set_gates, sample; or in one call: run_window),
// then ends it (end_window: the plant runs to the window end and its state is the window's truth).
// Every call first advances the plant to the event's tick; ticks never go backwards.
#ifndef HFI_PLANT_LOOP_H
#define HFI_PLANT_LOOP_H

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

extern "C" {
#pragma GCC visibility push(default)   // imported from libhfiplant.so (the hls library hides its own)
#include "plant_api.h"
#pragma GCC visibility pop
#include "plant_records.h"
}

class PlantLoop {
public:
    // The problem of a run's setup ("" if none): half 256..65535, n_windows >= 1, one speed reference
    // per window, adc_bits 1..16.
    static std::string check(long long half, long long n_windows, const int32_t *speed_ref, int adc_bits);
    // The plant stays owned by the caller; speed_ref (n_windows values) is copied.
    PlantLoop(plant *pl, long long half, long long n_windows, const int32_t *speed_ref, int adc_bits);

    long long period() const { return 2 * half_; }
    long long n_windows() const { return n_windows_; }
    long long window_start(long long k) const { return k * period() + half_ / 2; }
    long long window_end(long long k) const { return window_start(k) + period(); }
    // Windows ended so far; the next window to end, and its end tick.
    long long windows_ended() const { return (long long)truth.size(); }
    long long next_window_end() const { return window_end(windows_ended()); }
    // The firmware's speed reference of window k (0 <= k < n_windows).
    int32_t speed_ref(long long k) const { return speed_ref_[(size_t)k]; }
    // The ADC's mid-scale code (what a converter without a plant sample reads).
    int mid_code() const { return 1 << (adc_bits_ - 1); }

    // Per event. false: the plant refused it (error() says which and why).
    bool set_gates(long long tick, int mask);                   // records the edge
    bool sample(long long tick, int *adc_a, int *adc_b, int *adc_vdc);   // records the sample
    bool end_window();                                          // records the truth
    // The window windows_ended() in one plant call: gate edges (e_ticks, e_masks) and samples (s_ticks,
    // codes into adc: PLANT_ADC_CHANNELS per sample, currents a, b, c and the dc link), recorded, then
    // end_window().
    bool run_window(const std::vector<long long> &e_ticks, const std::vector<int> &e_masks,
                    const std::vector<long long> &s_ticks, std::vector<int> &adc);
    // run_window for a window whose samples may trip the hardware overcurrent comparator (spec 3.7): the
    // plant's moment before the window is kept, and `cut` (given the window's codes) returns true when it cut
    // e_ticks / e_masks (the gates off from a tick inside the window); the plant then runs the window again from
    // its start with the cut edges, and those are recorded.
    bool run_window_checked(std::vector<long long> &e_ticks, std::vector<int> &e_masks,
                            const std::vector<long long> &s_ticks, std::vector<int> &adc,
                            const std::function<bool(const std::vector<int> &)> &cut);

    const std::string &error() const { return error_; }
    // Wall seconds spent inside the plant calls of run_window.
    double plant_seconds() const { return plant_seconds_; }

    std::vector<gate_edge> edges;
    std::vector<adc_sample> samples;
    std::vector<plant_state> truth;     // at every window end

private:
    bool refused(const char *what, long long tick, int status);
    bool record_sample(long long tick, int a, int b, int vdc);
    bool plant_call(const std::vector<long long> &e_ticks, const std::vector<int> &e_masks,
                    const std::vector<long long> &s_ticks, std::vector<int> &adc);
    bool record_window(const std::vector<long long> &e_ticks, const std::vector<int> &e_masks,
                       const std::vector<long long> &s_ticks, const std::vector<int> &adc);
    std::vector<char> snapshot_;

    plant *pl_;
    long long half_, n_windows_;
    std::vector<int32_t> speed_ref_;
    int adc_bits_;
    std::string error_;
    double plant_seconds_ = 0;
};

// Copies the records [from, from + n) of v into dst; -1 if that range is not inside v.
template <typename T> int copy_records(const std::vector<T> &v, long long from, long long n, void *dst)
{
    if (from < 0 || n < 0 || from + n > (long long)v.size())
        return -1;
    if (n)
        std::memcpy(dst, v.data() + from, (size_t)n * sizeof(T));
    return 0;
}

// Writes msg into err (err_len bytes, truncated, NUL-terminated) if err is given.
void set_message(char *err, int err_len, const std::string &msg);

#endif
