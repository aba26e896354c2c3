// The one status vocabulary of the core: the public statuses (lemke.Status in Python, the C
// API's LEMKE_* codes, the same numbers) and the kernels' own codes, declared here together
// so that no kernel code takes a public status's number where the two can meet.
//
// Rules: a kernel's own code is negative (a public status is 0..8; a success is SOLVED's 0)
// and distinct from every other kernel's; one meaning, one number (NOT_FINITE); each is
// listed in KERNEL_CODES (the end of this file; tests/test_status_codes.py reads this file
// and fails on one missing there, the C API's static_asserts on one without a LEMKE_*
// status). Each front maps its kernel's codes to a Status (ARCHITECTURE.md, "The seam",
// subsection "Status codes", says where).
#pragma once

#include "budget.hpp"

namespace lemke {

// The public statuses (the codes of lemke.Status and of lemke.h's enum lemke_status).
enum Status : int {
    SOLVED = 0,
    MAX_PIVOTS = 1,
    RAY_TERMINATION = 2,
    NUMERICAL_FAILURE = 3,
    CYCLING = 6,
    TIME_LIMIT = 7,    // the thread's deadline passed (budget.hpp)
    INTERRUPTED = 8,   // lemke_interrupt() or SIGINT (budget.hpp)
};

// A run stopped by its budget: drivers try nothing more.
static_assert(TIME_LIMIT == STOP_TIME_LIMIT && INTERRUPTED == STOP_INTERRUPTED, "budget.hpp");
inline bool is_stop(int code) { return code == TIME_LIMIT || code == INTERRUPTED; }

// --- the kernels' own codes: negative ------------------------------------------------------

// Every kernel: a NaN or an infinity in the data (or sizes that do not match): nothing done.
// The C API's LEMKE_NOT_FINITE has this number (capi.cpp passes it through).
constexpr int NOT_FINITE = -1;

// The LCP driver (lcp.hpp: RunResult.code, beside the Status codes). Mapped to SOLVED by
// lcp_status (below; in Python by _layout.public_status), the one mapping each side.
constexpr int TRIVIAL = -2;  // q >= 0: z = 0

// The box LCP engine (boxed.hpp: SolveResult.code and front's code, beside the Status codes).
// _blcp.py maps every negative code to NUMERICAL_FAILURE or an error; the C API maps every
// kernel code through capi_status.hpp's c_status alone (LEMKE_INVALID_ARGUMENT's -3 and
// LEMKE_OUT_OF_MEMORY's -4 are BAD_BOUNDS's and SINGULAR's numbers: no code passes unmapped).
namespace boxed {
constexpr int NOT_FINITE = lemke::NOT_FINITE;  // M or q has a NaN or an infinity, or lo/hi a NaN
constexpr int BAD_BOUNDS = -3;   // some lo_i > hi_i, or lo_i = +inf, or hi_i = -inf
constexpr int SINGULAR = -4;     // a warm start's basis cannot be made basic
constexpr int BAD_FINDEX = -5;   // a friction index the front refuses
constexpr int UNDECIDED = -6;    // front: the friction check failed
constexpr int NEED_RUN = -7;     // front: a run must decide
}  // namespace boxed

// The games engine (games.hpp: LHResult.status and TraceResult.status, beside the Status
// codes). Mapped to a Status by _games.py's _status alone.
namespace games {
constexpr int NOT_FINITE = lemke::NOT_FINITE;  // a payoff is NaN or infinite: nothing done
constexpr int UNCHECKED = -8;  // every label present, at a point that fails the check
}  // namespace games

// The MLCP reduction (mlcp.hpp: ReduceResult.code, its own variable): MLCP_OK is SOLVED's 0,
// the failures negative (the oracle's were 1 and 2, MAX_PIVOTS's and RAY_TERMINATION's
// numbers). Mapped by _mlcp.py (INCONSISTENT: PRIMAL_INFEASIBLE; SINGULAR: NUMERICAL_FAILURE).
constexpr int MLCP_OK = SOLVED;
constexpr int MLCP_INCONSISTENT = -9;  // an equation reads 0 = c with c != 0
constexpr int MLCP_SINGULAR = -10;     // no exchange makes the free block nonsingular

// The QP kernels (qp.hpp: Result.code, beside TIME_LIMIT and INTERRUPTED, the LCP or a
// set-up phase stopped by its budget): OK is SOLVED's 0, the rest negative (the oracle's
// were 1-6 and 9, MAX_PIVOTS .. CYCLING's numbers among them). _qp.py and
// python_front_qp.cpp go on by name, Status(code) only on a stop.
namespace qp {
constexpr int OK = SOLVED;
constexpr int NOT_DEFINITE = -11;
constexpr int DEPENDENT_EQUALITIES = -12;
constexpr int NOT_SOLVED = -13;
constexpr int CHECK_FAILED = -14;
constexpr int BAD_INPUT = -15;
constexpr int NOT_APPLICABLE = -16;
constexpr int BAD_WARM = -17;  // a warm start with another number of pairs (Result.pairs: this QP's)
}  // namespace qp

// One descending chain from NOT_FINITE: every kernel's own code negative (none a Status)
// and distinct from every other kernel's.
static_assert(TRIVIAL < NOT_FINITE && boxed::BAD_BOUNDS < TRIVIAL && boxed::NEED_RUN < boxed::UNDECIDED &&
                  boxed::UNDECIDED < boxed::BAD_FINDEX && boxed::BAD_FINDEX < boxed::SINGULAR &&
                  boxed::SINGULAR < boxed::BAD_BOUNDS && games::UNCHECKED < boxed::NEED_RUN &&
                  MLCP_INCONSISTENT < games::UNCHECKED && MLCP_SINGULAR < MLCP_INCONSISTENT &&
                  qp::NOT_DEFINITE < MLCP_SINGULAR && qp::DEPENDENT_EQUALITIES < qp::NOT_DEFINITE &&
                  qp::NOT_SOLVED < qp::DEPENDENT_EQUALITIES && qp::CHECK_FAILED < qp::NOT_SOLVED &&
                  qp::BAD_INPUT < qp::CHECK_FAILED && qp::NOT_APPLICABLE < qp::BAD_INPUT &&
                  qp::BAD_WARM < qp::NOT_APPLICABLE,
              "the kernels' own codes: negative and distinct");

}  // namespace lemke

namespace lemke {

// --- every kernel code by name, and the LCP driver's codes as public statuses ---------------

// Every kernel's own code above, by name (its namespace's prefix, as the C++ spells it): the
// table that the C API's static_asserts walk (capi_status.hpp: each maps to a documented
// LEMKE_* value) and the tests enumerate (_core._kernel_codes; tests/test_status_codes.py
// reads this header and fails on a code declared above and missing here).
struct KernelCode {
    const char* name;
    int code;
};
inline constexpr KernelCode KERNEL_CODES[] = {
    {"NOT_FINITE", NOT_FINITE},
    {"TRIVIAL", TRIVIAL},
    {"boxed::NOT_FINITE", boxed::NOT_FINITE},
    {"boxed::BAD_BOUNDS", boxed::BAD_BOUNDS},
    {"boxed::SINGULAR", boxed::SINGULAR},
    {"boxed::BAD_FINDEX", boxed::BAD_FINDEX},
    {"boxed::UNDECIDED", boxed::UNDECIDED},
    {"boxed::NEED_RUN", boxed::NEED_RUN},
    {"games::NOT_FINITE", games::NOT_FINITE},
    {"games::UNCHECKED", games::UNCHECKED},
    {"MLCP_OK", MLCP_OK},
    {"MLCP_INCONSISTENT", MLCP_INCONSISTENT},
    {"MLCP_SINGULAR", MLCP_SINGULAR},
    {"qp::OK", qp::OK},
    {"qp::NOT_DEFINITE", qp::NOT_DEFINITE},
    {"qp::DEPENDENT_EQUALITIES", qp::DEPENDENT_EQUALITIES},
    {"qp::NOT_SOLVED", qp::NOT_SOLVED},
    {"qp::CHECK_FAILED", qp::CHECK_FAILED},
    {"qp::BAD_INPUT", qp::BAD_INPUT},
    {"qp::NOT_APPLICABLE", qp::NOT_APPLICABLE},
    {"qp::BAD_WARM", qp::BAD_WARM},
};

// The LCP driver's code (RunResult.code: a Status, NOT_FINITE or TRIVIAL) as a public
// status: TRIVIAL (q >= 0: z = 0, checked) is SOLVED, every other code is itself (NOT_FINITE:
// each front reports the bad data its own way). The one place in C++ where TRIVIAL becomes
// SOLVED (python_front.cpp, the C API through capi_status.hpp); Python's is
// _layout.public_status.
constexpr int lcp_status(int code) { return code == TRIVIAL ? SOLVED : code; }

// A run of the LCP driver whose answer is final: checked (ok) and solved (TRIVIAL included)
// or a ray (the kernel checked it). The rest go on in the fronts' recoveries.
constexpr bool lcp_settled(int code, bool ok) {
    return ok && (lcp_status(code) == SOLVED || code == RAY_TERMINATION);
}

}  // namespace lemke
