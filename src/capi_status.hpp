// The C API's one mapping from the core's codes to its public statuses (include/lemke.h's
// enum lemke_status, an ABI: its numbers never change). The public statuses the C API
// returns are the core's Status numbers (static_asserts below); the kernels' own codes are
// negative like the C API's bad-input codes, and LEMKE_INVALID_ARGUMENT (-3) and
// LEMKE_OUT_OF_MEMORY (-4) have the numbers of boxed::BAD_BOUNDS and boxed::SINGULAR: a
// kernel code therefore reaches a caller only through c_status (capi.cpp returns no kernel
// code unmapped), which maps every code of status.hpp's KERNEL_CODES to a documented
// LEMKE_* value (checked here at compile time and by tests/test_status_codes.py through
// _core._c_status).
#pragma once

#include "lemke.h"
#include "lemke/status.hpp"

namespace lemke {

// A core code (a Status or a kernel's own code) as a LEMKE_* status. The C API runs the LCP
// driver and the box engine; the codes of the other kernels are mapped all the same (the
// data refused: LEMKE_INVALID_ARGUMENT; no checked answer: LEMKE_NUMERICAL_FAILURE), so that
// no code is left without one. An unknown code gives UNMAPPED, which no static_assert below
// lets a KERNEL_CODES entry reach.
constexpr int UNMAPPED = 1 << 30;
constexpr int c_status(int code) {
    switch (code) {
        case SOLVED:
        case MAX_PIVOTS:
        case RAY_TERMINATION:
        case NUMERICAL_FAILURE:
        case CYCLING:
        case TIME_LIMIT:
        case INTERRUPTED: return code;  // the same numbers (below)
        case NOT_FINITE: return LEMKE_NOT_FINITE;  // (boxed::, games::NOT_FINITE too)
        case TRIVIAL: return LEMKE_SOLVED;  // q >= 0: z = 0 (lcp_status)
        case boxed::BAD_BOUNDS:
        case boxed::BAD_FINDEX:
        case MLCP_INCONSISTENT:
        case qp::BAD_INPUT:
        case qp::NOT_APPLICABLE:
        case qp::BAD_WARM: return LEMKE_INVALID_ARGUMENT;
        case boxed::SINGULAR:
        case boxed::UNDECIDED:
        case boxed::NEED_RUN:
        case games::UNCHECKED:
        case MLCP_SINGULAR:
        case qp::NOT_DEFINITE:
        case qp::DEPENDENT_EQUALITIES:
        case qp::NOT_SOLVED:
        case qp::CHECK_FAILED: return LEMKE_NUMERICAL_FAILURE;
        default: return UNMAPPED;
    }
}

// A value of enum lemke_status (lemke.h documents each).
constexpr bool documented(int s) {
    switch (s) {
        case LEMKE_SOLVED:
        case LEMKE_MAX_PIVOTS:
        case LEMKE_RAY_TERMINATION:
        case LEMKE_NUMERICAL_FAILURE:
        case LEMKE_CYCLING:
        case LEMKE_TIME_LIMIT:
        case LEMKE_INTERRUPTED:
        case LEMKE_NOT_FINITE:
        case LEMKE_INVALID_ARGUMENT:
        case LEMKE_OUT_OF_MEMORY: return true;
        default: return false;
    }
}

// Every kernel code maps, by a case of its own in c_status (the default is UNMAPPED), to a
// documented LEMKE_* value; boxed::BAD_BOUNDS (-3) maps to LEMKE_INVALID_ARGUMENT (-3) by
// that case, boxed::SINGULAR (-4) to LEMKE_NUMERICAL_FAILURE, not LEMKE_OUT_OF_MEMORY.
constexpr bool every_code_mapped() {
    for (const KernelCode& k : KERNEL_CODES)
        if (!documented(c_status(k.code))) return false;
    return c_status(boxed::SINGULAR) != LEMKE_OUT_OF_MEMORY;
}
static_assert(every_code_mapped(), "a kernel code without a LEMKE_* status: add it to c_status");

static_assert(int(LEMKE_SOLVED) == SOLVED && int(LEMKE_MAX_PIVOTS) == MAX_PIVOTS &&
                  int(LEMKE_RAY_TERMINATION) == RAY_TERMINATION &&
                  int(LEMKE_NUMERICAL_FAILURE) == NUMERICAL_FAILURE &&
                  int(LEMKE_CYCLING) == CYCLING && int(LEMKE_TIME_LIMIT) == TIME_LIMIT &&
                  int(LEMKE_INTERRUPTED) == INTERRUPTED && int(LEMKE_NOT_FINITE) == NOT_FINITE,
              "the C API's statuses are the core's numbers");

}  // namespace lemke
