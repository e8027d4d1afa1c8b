// The thread pool behind run_parallel (parallel.hpp).
//
// One pool per process (a forked child makes its own), created at the first parallel call, never destroyed (its threads are blocked or
// spinning on it when the process exits, so it must outlive every static destructor). A run publishes a job
// and bumps a generation counter; each worker spins on the counter for a short while after its last job
// (the stages of a frame follow each other within microseconds) and then sleeps on a condition variable,
// so an idle process costs no CPU. The caller runs part 0 itself and waits for the workers the same way.
// One run at a time: a call that finds the pool busy (another thread's run, or a call from inside a job)
// starts threads of its own, as run_parallel did before there was a pool.
#include "raster/parallel.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <pthread.h>
#include <mutex>
#include <system_error>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SHADELAB_PAUSE() _mm_pause()
#else
#define SHADELAB_PAUSE() std::this_thread::yield()
#endif

namespace shadelab::detail {
namespace {

// How long a waiting thread spins before it sleeps: longer than the gap between two stages of a frame,
// short enough that a worker left spinning after the last stage barely competes with the shading kernel's
// threads.
constexpr std::chrono::microseconds kSpin{50};

// Spins until pred() holds or kSpin has passed; true if it holds.
template <class Pred>
bool spin_until(const Pred& pred) {
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (;;) {
        for (int k = 0; k < 64; ++k) {
            if (pred()) return true;
            SHADELAB_PAUSE();
        }
        if (std::chrono::steady_clock::now() >= until) return pred();
    }
}

// Records the first exception of a run; the others are dropped (one error line reaches the user).
class FirstError {
public:
    void capture() {
        std::lock_guard<std::mutex> lock(m_);
        if (!e_) e_ = std::current_exception();
    }
    void rethrow() {
        std::exception_ptr e;
        {
            std::lock_guard<std::mutex> lock(m_);
            std::swap(e, e_);
        }
        if (e) std::rethrow_exception(e);
    }

private:
    std::mutex m_;
    std::exception_ptr e_;
};

// Part i of a job, its exception (if any) recorded in `error`.
void run_part(ParallelCall call, const void* fn, int i, FirstError& error) {
    try {
        call(fn, i);
    } catch (...) {
        error.capture();
    }
}

// fn(i) for i in [1, n) on threads started for this call alone (the pool is busy or cannot start threads).
void run_on_new_threads(int n, ParallelCall call, const void* fn, FirstError& error) {
    auto part = [&](int i) { run_part(call, fn, i, error); };
    std::vector<std::thread> threads;
    int started = 1;
    try {
        threads.reserve(std::size_t(n - 1));
        for (; started < n; ++started) threads.emplace_back(part, started);
    } catch (...) {
    }
    part(0);
    for (int i = started; i < n; ++i) part(i);
    for (auto& t : threads) t.join();
}

class Pool {
public:
    // Runs the job on the pool; false (nothing run) if the pool is busy.
    bool try_run(int n, ParallelCall call, const void* fn, FirstError& error) {
        bool expected = false;
        if (!busy_.compare_exchange_strong(expected, true, std::memory_order_acquire)) return false;
        struct Release {
            std::atomic<bool>& busy;
            ~Release() { busy.store(false, std::memory_order_release); }
        } release{busy_};
        grow(n - 1);
        const int workers = workers_;
        if (workers == 0) return false;   // no thread could be started
        job_ = Job{n, call, fn, &error};
        pending_.store(workers, std::memory_order_relaxed);
        generation_.fetch_add(1, std::memory_order_release);
        wake_workers();
        run_part(0);
        // Parts beyond the workers (a pool that could not grow to n - 1 threads) run here.
        for (int i = workers + 1; i < n; ++i) run_part(i);
        wait_for_workers();
        return true;
    }

private:
    struct Job {
        int n = 0;
        ParallelCall call = nullptr;
        const void* fn = nullptr;
        FirstError* error = nullptr;
    };

    void run_part(int i) { detail::run_part(job_.call, job_.fn, i, *job_.error); }

    // Starts workers until there are `want` of them (fewer if a thread cannot be started).
    void grow(int want) {
        while (workers_ < want) {
            const int index = workers_ + 1;
            // The generation before this call's job: the new worker must see the job's bump as fresh.
            const std::uint64_t seen = generation_.load(std::memory_order_relaxed);
            try {
                std::thread([this, index, seen] { work(index, seen); }).detach();
            } catch (const std::system_error&) {
                return;
            }
            ++workers_;
        }
    }

    void wake_workers() {
        std::lock_guard<std::mutex> lock(m_);
        if (sleeping_workers_ > 0) work_cv_.notify_all();
    }

    void wait_for_workers() {
        auto done = [&] { return pending_.load(std::memory_order_acquire) == 0; };
        if (spin_until(done)) return;
        std::unique_lock<std::mutex> lock(m_);
        caller_sleeping_ = true;
        done_cv_.wait(lock, done);
        caller_sleeping_ = false;
    }

    // Worker `index` (part `index` of each job with n > index; every worker acknowledges every job), started
    // when the generation was `seen`.
    void work(int index, std::uint64_t seen) {
        for (;;) {
            auto fresh = [&] { return generation_.load(std::memory_order_acquire) != seen; };
            if (!spin_until(fresh)) {
                std::unique_lock<std::mutex> lock(m_);
                ++sleeping_workers_;
                work_cv_.wait(lock, fresh);
                --sleeping_workers_;
            }
            seen = generation_.load(std::memory_order_acquire);
            if (index < job_.n) run_part(index);
            if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                std::lock_guard<std::mutex> lock(m_);
                if (caller_sleeping_) done_cv_.notify_one();
            }
        }
    }

    std::atomic<bool> busy_{false};
    int workers_ = 0;                    // started (detached) worker threads: parts 1 .. workers_
    Job job_;                            // written only while every worker is between jobs
    std::atomic<std::uint64_t> generation_{0};
    std::atomic<int> pending_{0};
    std::mutex m_;
    std::condition_variable work_cv_, done_cv_;
    int sleeping_workers_ = 0;   // guarded by m_
    bool caller_sleeping_ = false;   // guarded by m_
};

// The process's pool: never destroyed (see the top of this file). A child made by fork() has none of the
// parent's threads (Python's multiprocessing forks a process that has rasterised), so it starts a pool of its
// own; the parent's is left unused there.
Pool* g_pool = nullptr;

Pool& pool() {
    static const bool made = [] {
        g_pool = new Pool();
        ::pthread_atfork(nullptr, nullptr, [] { g_pool = new Pool(); });
        return true;
    }();
    (void)made;
    return *g_pool;
}

}  // namespace

void run_parallel_erased(int n, ParallelCall call, const void* fn) {
    FirstError error;
    if (!pool().try_run(n, call, fn, error)) run_on_new_threads(n, call, fn, error);
    error.rethrow();
}

}  // namespace shadelab::detail
