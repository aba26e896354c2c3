// Budgets: a time limit and an interrupt for every engine's pivot loop.
//
// Every engine run makes one Poll and calls poll.tick(work) before each pivot, with the
// pivot's work in multiply-adds (about rows x columns). tick costs an add and a compare;
// once the work since the last look passes POLL_WORK (some tens of microseconds), it looks:
//   - the interrupt counter (bumped by lemke_interrupt(), or by the SIGINT listener):
//     changed since the Poll began -> INTERRUPTED;
//   - the calling thread's deadline (set by a DeadlineScope; none by default): passed ->
//     TIME_LIMIT.
// The first tick of a run always looks, so a run that starts past its deadline makes no
// pivot. Once a run has done ARM_WORK (about a millisecond), its Poll arms the SIGINT
// listener when the listener is enabled (the Python module enables it; the C API never
// does: C programs call lemke_interrupt() from their own handler); the listener chains to
// the handler it replaced (Python's), and the last Poll to end restores that handler.
// Drivers that run several engines stop at the first TIME_LIMIT or INTERRUPTED.
#pragma once
#include <atomic>
#include <cstdint>

#include "span.hpp"

namespace lemke {

constexpr std::int64_t POLL_WORK = 1 << 15;
constexpr std::int64_t ARM_WORK = 1 << 22;

// Interrupts so far (any thread, or a signal handler: lock-free).
std::uint64_t interrupts_seen();
void interrupt_all();

// The SIGINT listener: enabled once by the Python module; arm / disarm count the runs
// that asked for it.
void enable_sigint_listener(bool on);
bool arm_sigint_listener();
void disarm_sigint_listener();

// The calling thread's deadline, in steady-clock nanoseconds (0: none).
std::int64_t thread_deadline();
std::int64_t now_ns();

// Sets the calling thread's deadline for its lifetime (seconds from now; inf or < 0:
// none), restoring the previous one at the end.
class DeadlineScope {
    std::int64_t saved_;

public:
    explicit DeadlineScope(double seconds);
    ~DeadlineScope();
    DeadlineScope(const DeadlineScope&) = delete;
    DeadlineScope& operator=(const DeadlineScope&) = delete;
};
// Without a scope (the Python fronts): tighten the deadline to `seconds` from now (an
// earlier one stands; seconds < 0 or inf: no new one) and return the one it replaces, for
// restore_thread_deadline (also how a worker thread takes its caller's deadline).
std::int64_t tighten_thread_deadline(double seconds);
void restore_thread_deadline(std::int64_t deadline);

// Status codes of a stop (the values of Status::TIME_LIMIT and Status::INTERRUPTED).
constexpr int STOP_TIME_LIMIT = 7;
constexpr int STOP_INTERRUPTED = 8;

// STOP_TIME_LIMIT when the calling thread's deadline has passed, else -1: for drivers
// between set-up phases that take long before any pivot (the QP's factorizations).
inline int deadline_passed() {
    std::int64_t d = thread_deadline();
    return d != 0 && now_ns() >= d ? STOP_TIME_LIMIT : -1;
}

// The calling thread's progress probe (none by default): at each look a run stores its
// pivots so far there, and stops (INTERRUPTED) once another thread has asked it to. No
// callback runs in the solving thread: the thread that reports reads the probe.
struct ProgressHook {
    std::atomic<std::int64_t> pivots{0};
    std::atomic<bool> stop{false};
};
ProgressHook* thread_progress();
void set_thread_progress(ProgressHook* hook);

class Poll {
    std::int64_t work_ = POLL_WORK;  // the first tick looks
    std::int64_t total_ = 0;
    std::int64_t pivots_ = 0;
    std::int64_t deadline_;
    std::uint64_t seen_;
    ProgressHook* progress_;
    int stopped_ = -1;
    bool armed_ = false;
    bool tried_ = false;
    int look();

public:
    Poll()
        : deadline_(thread_deadline()), seen_(interrupts_seen()), progress_(thread_progress()) {}
    ~Poll() {
        if (armed_) disarm_sigint_listener();
    }
    Poll(const Poll&) = delete;
    Poll& operator=(const Poll&) = delete;
    // -1: go on; else STOP_TIME_LIMIT or STOP_INTERRUPTED (and so at every later tick).
    int tick(std::int64_t work) {
        work_ += work;
        ++pivots_;
        return work_ < POLL_WORK ? -1 : look();
    }
    // A look now, whatever the work since the last one: before a step that takes long at
    // once (a refactorization).
    int now() { return look(); }
};

}  // namespace lemke
