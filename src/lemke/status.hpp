// The one status vocabulary of the core: the public statuses (lemke.Status in Python, the C
// API's LEMKE_* codes, the same numbers) and the kernels' own codes, declared here together
// so that no kernel code takes a public status's number where the two can meet.
//
// Rules: a kernel's own code is negative (a public status is 0..8; a success is SOLVED's 0),
// but for the QP kernels' (below: none a number of the statuses they meet); codes that can
// come back in the same variable are distinct; one meaning, one number (NOT_FINITE). Each
// front maps its kernel's codes to a Status (ARCHITECTURE.md, "The seam", its "status
// codes" row, says where, and what is left).
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
// _lcp.py, python_front.cpp and capi.cpp.
constexpr int TRIVIAL = -2;  // q >= 0: z = 0

// The box LCP engine (boxed.hpp: SolveResult.code and front's code, beside the Status codes).
// _blcp.py maps every negative code to NUMERICAL_FAILURE or an error; capi.cpp maps them to
// LEMKE_NOT_FINITE or LEMKE_INVALID_ARGUMENT (whose -3 and -4 are BAD_BOUNDS's and
// SINGULAR's numbers: they never pass through).
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

// The QP kernels (qp.hpp: Result.code): their own numbers, kept (the QP front, its tests and
// the frozen references use them), none a stop's: a kernel's code is one of these or
// TIME_LIMIT / INTERRUPTED (the LCP or a set-up phase stopped by its budget), which _qp.py
// and python_front_qp.cpp test for by number (Status(code) only on a stop). 1-6 are public numbers
// (MAX_PIVOTS .. CYCLING) that never meet them there: not yet negative (ARCHITECTURE.md).
namespace qp {
constexpr int OK = SOLVED;
constexpr int NOT_DEFINITE = 1;
constexpr int DEPENDENT_EQUALITIES = 2;
constexpr int NOT_SOLVED = 3;
constexpr int CHECK_FAILED = 4;
constexpr int BAD_INPUT = 5;
constexpr int NOT_APPLICABLE = 6;
constexpr int BAD_WARM = 9;  // a warm start with another number of pairs (Result.pairs: this QP's)
static_assert(OK < NOT_DEFINITE && NOT_DEFINITE < DEPENDENT_EQUALITIES &&
                  DEPENDENT_EQUALITIES < NOT_SOLVED && NOT_SOLVED < CHECK_FAILED &&
                  CHECK_FAILED < BAD_INPUT && BAD_INPUT < NOT_APPLICABLE &&
                  NOT_APPLICABLE < TIME_LIMIT && INTERRUPTED < BAD_WARM,
              "the QP kernels' codes: distinct, none a stop's (7, 8)");
}  // namespace qp

// Distinct where they meet: each kernel's codes among themselves and with TRIVIAL (the
// LCP's), and none a Status.
static_assert(TRIVIAL < NOT_FINITE && boxed::BAD_BOUNDS < TRIVIAL && boxed::NEED_RUN < boxed::UNDECIDED &&
                  boxed::UNDECIDED < boxed::BAD_FINDEX && boxed::BAD_FINDEX < boxed::SINGULAR &&
                  boxed::SINGULAR < boxed::BAD_BOUNDS && games::UNCHECKED < boxed::NEED_RUN &&
                  MLCP_INCONSISTENT < games::UNCHECKED && MLCP_SINGULAR < MLCP_INCONSISTENT,
              "the kernels' own codes: negative and distinct");

}  // namespace lemke
