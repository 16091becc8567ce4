// stop.hpp: how a render learns that it must stop (RenderOptions::deadline and ::stop).
//
// Implements: StopSignal, read with one relaxed atomic load (or two, with the caller's flag)
// wherever the pipeline may stop: between draws, between the primitives setup and traversal
// hand on, and between a band's primitives on each shading thread. A watchdog thread, started
// only when the render has a deadline, sleeps until it and then raises the signal, so no
// check reads the clock. `throw_if_requested` throws RenderStopped; the shading threads only
// test `requested` and return, and the thread that runs them throws once all have returned.
//
// Deliberately does not: stop inside a primitive's pixels, or change any arithmetic: a render
// that is not stopped computes exactly what it would without a signal.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "refraster/renderer.hpp"

namespace refraster::detail {

class StopSignal {
  public:
    // A signal raised by `external` (may be null), and at `deadline` when there is one.
    StopSignal(std::optional<std::chrono::steady_clock::time_point> deadline,
               const std::atomic<bool>* external)
        : external_(external), deadline_(deadline) {
        if (!deadline_) return;
        if (std::chrono::steady_clock::now() >= *deadline_) {
            raised_.store(true, std::memory_order_relaxed);
            return;
        }
        watchdog_ = std::thread([this] {
            std::unique_lock lock(mutex_);
            if (!wake_.wait_until(lock, *deadline_, [this] { return done_; }))
                raised_.store(true, std::memory_order_relaxed);
        });
    }
    ~StopSignal() {
        if (!watchdog_.joinable()) return;
        {
            const std::lock_guard lock(mutex_);
            done_ = true;
        }
        wake_.notify_all();
        watchdog_.join();
    }
    StopSignal(const StopSignal&) = delete;
    StopSignal& operator=(const StopSignal&) = delete;

    bool requested() const noexcept {
        return raised_.load(std::memory_order_relaxed) ||
               (external_ != nullptr && external_->load(std::memory_order_relaxed));
    }
    void throw_if_requested() const {
        if (!requested()) return;
        throw RenderStopped(raised_.load(std::memory_order_relaxed)
                                ? "the render passed its deadline and stopped"
                                : "the render was asked to stop");
    }

  private:
    std::atomic<bool> raised_{false};
    const std::atomic<bool>* external_;
    std::optional<std::chrono::steady_clock::time_point> deadline_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool done_ = false;
    std::thread watchdog_;
};

}  // namespace refraster::detail
