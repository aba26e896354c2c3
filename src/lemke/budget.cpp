// Budgets (budget.hpp): the interrupt counter, the SIGINT listener, the thread's deadline.
#include "budget.hpp"

#include <chrono>
#include <cmath>
#include <mutex>

#ifndef _WIN32
#include <signal.h>
#endif

namespace lemke {

namespace {

std::atomic<std::uint64_t> g_interrupts{0};
std::atomic<bool> g_listener_enabled{false};
thread_local std::int64_t t_deadline = 0;
thread_local ProgressHook* t_progress = nullptr;

#ifndef _WIN32
std::mutex g_listener_mutex;
int g_listeners = 0;           // runs holding the listener armed (under the mutex)
struct sigaction g_previous;   // the handler the listener replaced (read by the handler)

// Counts the interrupt, then does what the replaced handler does (Python's: it notes the
// signal and raises KeyboardInterrupt in the main thread at its next bytecode).
extern "C" void on_sigint(int sig, siginfo_t* info, void* context) {
    g_interrupts.fetch_add(1, std::memory_order_relaxed);
    if (g_previous.sa_flags & SA_SIGINFO) {
        if (g_previous.sa_sigaction != nullptr) g_previous.sa_sigaction(sig, info, context);
    } else if (g_previous.sa_handler != SIG_DFL && g_previous.sa_handler != SIG_IGN &&
               g_previous.sa_handler != nullptr) {
        g_previous.sa_handler(sig);
    }
}

bool is_function(const struct sigaction& a) {
    if (a.sa_flags & SA_SIGINFO) return a.sa_sigaction != nullptr;
    return a.sa_handler != SIG_DFL && a.sa_handler != SIG_IGN && a.sa_handler != nullptr;
}
#endif

}  // namespace

std::uint64_t interrupts_seen() { return g_interrupts.load(std::memory_order_relaxed); }

void interrupt_all() { g_interrupts.fetch_add(1, std::memory_order_relaxed); }

void enable_sigint_listener(bool on) { g_listener_enabled.store(on, std::memory_order_relaxed); }

bool arm_sigint_listener() {
#ifdef _WIN32
    return false;
#else
    if (!g_listener_enabled.load(std::memory_order_relaxed)) return false;
    std::lock_guard<std::mutex> lock(g_listener_mutex);
    if (g_listeners == 0) {
        struct sigaction current;
        if (sigaction(SIGINT, nullptr, &current) != 0) return false;
        // Only where a handler function is in force (Python's): with the default action
        // (end the process) or SIGINT ignored, the caller's choice stands.
        if (!is_function(current)) return false;
        // (never chain to itself: were the listener still in force, keep what it replaced)
        bool mine_already = (current.sa_flags & SA_SIGINFO) && current.sa_sigaction == on_sigint;
        if (!mine_already) g_previous = current;
        struct sigaction mine = current;
        mine.sa_sigaction = on_sigint;
        mine.sa_flags = (current.sa_flags | SA_SIGINFO) & ~SA_RESETHAND;
        if (sigaction(SIGINT, &mine, nullptr) != 0) return false;
    }
    ++g_listeners;
    return true;
#endif
}

void disarm_sigint_listener() {
#ifndef _WIN32
    std::lock_guard<std::mutex> lock(g_listener_mutex);
    if (g_listeners == 0 || --g_listeners > 0) return;
    struct sigaction current;
    // Restored only if the listener is still the handler (the program may have set another).
    if (sigaction(SIGINT, nullptr, &current) == 0 && (current.sa_flags & SA_SIGINFO) &&
        current.sa_sigaction == on_sigint)
        sigaction(SIGINT, &g_previous, nullptr);
#endif
}

std::int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

std::int64_t thread_deadline() { return t_deadline; }

ProgressHook* thread_progress() { return t_progress; }

void set_thread_progress(ProgressHook* hook) { t_progress = hook; }

static std::int64_t deadline_after(double seconds) {
    if (!(seconds >= 0.0) || !std::isfinite(seconds)) return 0;
    double ns = seconds * 1e9;
    if (ns > 4e18) return 0;  // centuries: no deadline
    std::int64_t d = now_ns() + static_cast<std::int64_t>(ns);
    return d == 0 ? 1 : d;
}

std::int64_t tighten_thread_deadline(double seconds) {
    std::int64_t previous = t_deadline, d = deadline_after(seconds);
    if (d != 0 && (previous == 0 || d < previous)) t_deadline = d;
    return previous;
}

void restore_thread_deadline(std::int64_t deadline) { t_deadline = deadline; }

DeadlineScope::DeadlineScope(double seconds) : saved_(t_deadline) {
    t_deadline = deadline_after(seconds);
}

DeadlineScope::~DeadlineScope() { t_deadline = saved_; }

int Poll::look() {
    total_ += work_;
    work_ = 0;
    if (stopped_ < 0) {
        if (interrupts_seen() != seen_) {
            stopped_ = STOP_INTERRUPTED;
        } else if (deadline_ != 0 && now_ns() >= deadline_) {
            stopped_ = STOP_TIME_LIMIT;
        } else if (!tried_ && total_ >= ARM_WORK) {
            tried_ = true;
            armed_ = arm_sigint_listener();
        }
        if (stopped_ < 0 && progress_ != nullptr) {
            // (pivots_ counts this tick's pivot, not yet made)
            progress_->pivots.store(pivots_ - 1, std::memory_order_relaxed);
            if (progress_->stop.load(std::memory_order_relaxed)) stopped_ = STOP_INTERRUPTED;
        }
    }
    if (stopped_ >= 0) work_ = POLL_WORK;  // from now on every tick says so
    return stopped_;
}

}  // namespace lemke
