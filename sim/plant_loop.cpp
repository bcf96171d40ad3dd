// plant_loop.cpp - the window sequencing around the C plant (plant_loop.h).
#include "plant_loop.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

std::string PlantLoop::check(long long half, long long n_windows, const int32_t *speed_ref, int adc_bits)
{
    if (half < 256 || half > 65535)
        return "half = " + std::to_string(half) + " is outside 256..65535";
    if (n_windows < 1 || speed_ref == nullptr)
        return "n_windows must be >= 1 with one speed reference per window";
    if (adc_bits < 1 || adc_bits > 16)
        return "adc_bits must be 1..16";
    return "";
}

PlantLoop::PlantLoop(plant *pl, long long half, long long n_windows, const int32_t *speed_ref, int adc_bits)
    : pl_(pl), half_(half), n_windows_(n_windows), speed_ref_(speed_ref, speed_ref + n_windows),
      adc_bits_(adc_bits)
{
    // the records' whole length at once (a sample per 100 ticks, the default 1 us grid at 100 MHz; six edges per half
    // period): grown by push_back they were copied and their pages touched about twice over (6-9 % of an hls run in
    // the kernel's page clearing, 2026-11-29); pages reserved and never written (a coarser grid, a faster tick) cost
    // no memory
    const long long per_us = std::max(2 * half / 100, 2LL);
    truth.reserve((size_t)n_windows);
    samples.reserve((size_t)(n_windows * per_us));
    edges.reserve((size_t)n_windows * 12);
}

bool PlantLoop::refused(const char *what, long long tick, int status)
{
    const char *why = plant_status_text(status);
    error_ = "window " + std::to_string(windows_ended()) + ": the plant refused " + what + " at tick " +
             std::to_string(tick) + " (status " + std::to_string(status) + ": " + why + ")";
    return false;
}

bool PlantLoop::record_sample(long long tick, int a, int b, int vdc)
{
    const int top = (1 << adc_bits_) - 1;
    if (a < 0 || a > top || b < 0 || b > top || vdc < 0 || vdc > top) {
        char msg[200];
        std::snprintf(msg, sizeof msg, "window %lld: ADC code (%d, %d, %d) at tick %lld is outside 0..%d (%d bits)",
                      windows_ended(), a, b, vdc, tick, top, adc_bits_);
        error_ = msg;
        return false;
    }
    samples.push_back(adc_sample{tick, a, b, vdc, 0});
    return true;
}

bool PlantLoop::set_gates(long long tick, int mask)
{
    int st = plant_advance(pl_, tick);
    if (st == 0)
        st = plant_set_gates(pl_, mask);
    if (st != 0)
        return refused("a gate mask", tick, st);
    edges.push_back(gate_edge{tick, mask});
    return true;
}

bool PlantLoop::sample(long long tick, int *adc_a, int *adc_b, int *adc_vdc)
{
    int adc[PLANT_ADC_CHANNELS];
    double analog[PLANT_ADC_CHANNELS];
    int st = plant_advance(pl_, tick);
    if (st == 0)
        st = plant_sample(pl_, adc, analog);
    if (st != 0)
        return refused("a sample", tick, st);
    *adc_a = adc[0];
    *adc_b = adc[1];
    *adc_vdc = adc[PLANT_ADC_VDC];
    return record_sample(tick, adc[0], adc[1], adc[PLANT_ADC_VDC]);
}

bool PlantLoop::end_window()
{
    const long long end = next_window_end();
    const int st = plant_advance(pl_, end);
    if (st != 0)
        return refused("the window end", end, st);
    plant_state ps;
    plant_get_state(pl_, &ps);
    truth.push_back(ps);
    return true;
}

bool PlantLoop::plant_call(const std::vector<long long> &e_ticks, const std::vector<int> &e_masks,
                           const std::vector<long long> &s_ticks, std::vector<int> &adc)
{
    const int n = int(s_ticks.size());
    adc.resize(PLANT_ADC_CHANNELS * size_t(n > 0 ? n : 1));
    auto t0 = std::chrono::steady_clock::now();
    const int st = plant_run(pl_, int(e_ticks.size()), e_ticks.data(), e_masks.data(), nullptr, n, s_ticks.data(),
                             adc.data(), nullptr, nullptr);
    plant_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (st != 0)
        return refused("the gate edges and samples", window_start(windows_ended()), st);
    return true;
}

bool PlantLoop::record_window(const std::vector<long long> &e_ticks, const std::vector<int> &e_masks,
                              const std::vector<long long> &s_ticks, const std::vector<int> &adc)
{
    for (size_t i = 0; i < e_ticks.size(); i++)
        edges.push_back(gate_edge{e_ticks[i], e_masks[i]});
    for (size_t i = 0; i < s_ticks.size(); i++)
        if (!record_sample(s_ticks[i], adc[PLANT_ADC_CHANNELS * i], adc[PLANT_ADC_CHANNELS * i + 1],
                           adc[PLANT_ADC_CHANNELS * i + PLANT_ADC_VDC]))
            return false;
    auto t0 = std::chrono::steady_clock::now();
    const bool ended = end_window();
    plant_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return ended;
}

bool PlantLoop::run_window(const std::vector<long long> &e_ticks, const std::vector<int> &e_masks,
                           const std::vector<long long> &s_ticks, std::vector<int> &adc)
{
    return plant_call(e_ticks, e_masks, s_ticks, adc) && record_window(e_ticks, e_masks, s_ticks, adc);
}

bool PlantLoop::run_window_checked(std::vector<long long> &e_ticks, std::vector<int> &e_masks,
                                   const std::vector<long long> &s_ticks, std::vector<int> &adc,
                                   const std::function<bool(const std::vector<int> &)> &cut)
{
    snapshot_.resize(plant_snapshot_size());
    plant_save(pl_, snapshot_.data());
    if (!plant_call(e_ticks, e_masks, s_ticks, adc))
        return false;
    if (cut(adc)) {
        plant_restore(pl_, snapshot_.data());
        if (!plant_call(e_ticks, e_masks, s_ticks, adc))
            return false;
    }
    return record_window(e_ticks, e_masks, s_ticks, adc);
}

void set_message(char *err, int err_len, const std::string &msg)
{
    if (err && err_len > 0)
        std::snprintf(err, size_t(err_len), "%s", msg.c_str());
}
