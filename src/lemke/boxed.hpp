// Lemke's method for the box LCP with bounded variables: n pairs, each z_i non-basic at a bound or
// basic, bound flips without a basis change, the friction index solved exactly on an
// extended box LCP (extend), and the one-call front of solve_blcp (front). Every sum in
// a fixed order, so the same bits on every instruction set (tests/data/frozen/ records them).
//
// Labels: 0..n-1 the w's, n..2n-1 the z's, 2n the artificial z0. Flags are one byte each
// (numpy's bool arrays).
#pragma once
#include <cstdint>
#include <vector>

#include "certify.hpp"  // the box checks (box_check, ...), with every kind's
#include "multiversion.hpp"
#include "pivoting.hpp"

namespace lemke {
namespace boxed {

// The kernel's own codes (besides the pivoting Status codes): NOT_FINITE, BAD_BOUNDS,
// SINGULAR, BAD_FINDEX, UNDECIDED, NEED_RUN, in status.hpp.
constexpr int PARTIAL = 4;       // solve's cov_mode flag: a warm basis that cannot be made
                                 // basic whole is kept in part (the z's the exchange pivots
                                 // could not make basic stay at their start bounds), not SINGULAR
constexpr int PREPARE = 0;       // front's phases
constexpr int SOLVED_RUN = 1;
constexpr double EXCHANGE_TOL = 1e-9;
constexpr double FAR = 1e20;

// The output buffer of one run (boxed.layout): [z | w | d | R | C | ray (n + 1)].
struct BoxLayout {
    idx n;
    idx z() const { return 0; }
    idx w() const { return n; }
    idx covering() const { return 2 * n; }
    idx row_scale() const { return 3 * n; }
    idx col_scale() const { return 4 * n; }
    idx ray() const { return 5 * n; }
    idx length() const { return 6 * n + 1; }
};

// The buffers of solve_blcp's one-call path (front, batch's islands, the C API), stated here
// once; every size and offset of them, in C++ and in Python (exported as
// lemke._core.boxed.layout), derives from this. A problem of n rows with nf friction rows
// is solved as the box LCP of N = n + 2 nf rows (extend); `friction`: a friction index is
// given (and n > 0), even one without friction rows.
//  buf:   the run's BoxLayout(N), then with a friction index the caller's answer
//         [z | w | lo | hi | R | C] (n each; lo, hi the bounds in force);
//  ints:  the final basis (N), then F: the friction rows (nf), their normal rows (nf);
//  work:  the extended problem (extend): Mx (N x N), qx, lox, hix (N each); empty when nf = 0.
struct FrontLayout {
    idx n, nf;
    bool friction;
    idx N() const { return n + 2 * nf; }
    BoxLayout run() const { return BoxLayout{N()}; }
    // the caller's answer (friction only)
    idx z() const { return run().length(); }
    idx w() const { return z() + n; }
    idx lo() const { return w() + n; }
    idx hi() const { return lo() + n; }
    idx row_scale() const { return hi() + n; }
    idx col_scale() const { return row_scale() + n; }
    idx length() const { return friction ? col_scale() + n : run().length(); }
    // where the answer's z and w sit: the caller's with a friction index, else the run's
    idx answer() const { return friction ? z() : run().z(); }
    // ints
    idx final() const { return 0; }
    idx friction_rows() const { return N(); }
    idx normal_rows() const { return N() + nf; }
    idx ints_length() const { return N() + 2 * nf; }
    // work
    idx work_M() const { return 0; }
    idx work_q() const { return N() * N(); }
    idx work_lo() const { return work_q() + N(); }
    idx work_hi() const { return work_lo() + N(); }
    idx work_length() const { return nf > 0 ? work_hi() + N() : 0; }
};

// What solve returns: (code, pivots, z0, ok, residual, k, m) of boxed.solve.
struct SolveResult {
    int code = 0;
    idx pivots = 0;
    double z0 = 0.0;
    bool ok = false;
    double residual = INF;
    idx k = 0, m = 0;
};

// The engine's workspace, laid out once per size (one per thread, reused). The offsets
// below state the layout; layout() sizes each array from the end of its last field:
// f:     (off doubles, so that T's first row starts on a 64-byte boundary) T (n x ld: rows
//        of n + 1 padded as TableauWork's, so pivot_now runs on whole aligned vectors; the
//        padding columns are zeroed and read by nobody) | qs, los, his, s0, z0s (n each) |
//        x, ray_lab (2n + 1 each) | the pivots' scratch prow (ld), col, col2 (n each: the
//        entering column, and the next one read during the pivot) |
//        lemke's keys, gaps, cc (n + 1 each), rlo, rhi, xb (n each) | equilibrate's 2n |
//        the pending pivots' U (n x block), V (block x ld), as TableauWork's, each from
//        a 64-byte boundary
// i:     basis (n), nonbasic (n + 1), pos (2n + 1), start_basis (n), cand (n + 1)
// flags: z_basic, z_hi (n each), is_basic (2n + 1), want (n), low (n + 1)
// chk:   the checks' scratch, outside the run's arrays (box_check 3n; check_scales 4n;
//        basis_point k (k + 2) + n; is_ray n), with chk_i (basis_point's n indices;
//        extend's friction ranks) and chk_f (front's rows of the extended matrix to make).
struct BoxedWork {
    std::vector<double> f, chk;
    std::vector<idx> i, chk_i;
    std::vector<std::uint8_t> flags, chk_f;
    idx n = -1;
    idx ld = 0;   // T's row stride: n + 1 rounded up to a multiple of 4 (n < 48) or 8
    idx off = 0;  // T's offset in f
    idx block = 1;  // pivots kept pending (tableau.hpp block_size)
    void layout(idx size);
    double* check_area(idx len);
    idx* check_indices(idx len);
    std::uint8_t* check_flags(idx len);  // (front's rows of the extended matrix to make)
    // offsets in f
    idx at_qs() const { return off + n * ld; }
    idx at_los() const { return at_qs() + n; }
    idx at_his() const { return at_los() + n; }
    idx at_s0() const { return at_his() + n; }
    idx at_z0s() const { return at_s0() + n; }
    idx at_x() const { return at_z0s() + n; }
    idx at_ray_lab() const { return at_x() + 2 * n + 1; }
    idx at_prow() const { return at_ray_lab() + 2 * n + 1; }
    idx at_col() const { return at_prow() + ld; }
    idx at_col2() const { return at_col() + n; }
    idx at_keys() const { return at_col2() + n; }
    idx at_gaps() const { return at_keys() + n + 1; }
    idx at_cc() const { return at_gaps() + n + 1; }
    idx at_rlo() const { return at_cc() + n + 1; }
    idx at_rhi() const { return at_rlo() + n; }
    idx at_xb() const { return at_rhi() + n; }
    idx at_eq_work() const { return at_xb() + n; }
    // U and V start on 64-byte boundaries as T does (flush reads V's rows as whole vectors)
    idx at_U() const { return off + (at_eq_work() + 2 * n - off + 7) / 8 * 8; }
    idx at_V() const { return off + (at_U() + n * block - off + 7) / 8 * 8; }
    idx f_length() const { return at_V() + block * ld; }
    // offsets in i
    idx at_nonbasic() const { return n; }
    idx at_pos() const { return at_nonbasic() + n + 1; }
    idx at_start_basis() const { return at_pos() + 2 * n + 1; }
    idx at_cand() const { return at_start_basis() + n; }
    idx i_length() const { return at_cand() + n + 1; }
    // offsets in flags
    idx at_z_hi() const { return n; }
    idx at_is_basic() const { return at_z_hi() + n; }
    idx at_want() const { return at_is_basic() + 2 * n + 1; }
    idx at_low() const { return at_want() + n; }
    idx flags_length() const { return at_low() + n + 1; }
    Mat<double> T() { return Mat<double>(f.data() + off, n, n + 1, ld); }
    double* qs() { return f.data() + at_qs(); }
    double* los() { return f.data() + at_los(); }
    double* his() { return f.data() + at_his(); }
    double* s0() { return f.data() + at_s0(); }
    double* z0s() { return f.data() + at_z0s(); }
    double* x() { return f.data() + at_x(); }
    double* ray_lab() { return f.data() + at_ray_lab(); }
    double* prow() { return f.data() + at_prow(); }
    double* col() { return f.data() + at_col(); }
    double* col2() { return f.data() + at_col2(); }
    double* keys() { return f.data() + at_keys(); }
    double* gaps() { return f.data() + at_gaps(); }
    double* cc() { return f.data() + at_cc(); }
    double* rlo() { return f.data() + at_rlo(); }
    double* rhi() { return f.data() + at_rhi(); }
    double* xb() { return f.data() + at_xb(); }
    double* eq_work() { return f.data() + at_eq_work(); }
    double* U() { return f.data() + at_U(); }
    double* V() { return f.data() + at_V(); }
    idx* basis() { return i.data(); }
    idx* nonbasic() { return i.data() + at_nonbasic(); }
    idx* pos() { return i.data() + at_pos(); }
    idx* start_basis() { return i.data() + at_start_basis(); }
    idx* cand() { return i.data() + at_cand(); }
    std::uint8_t* z_basic() { return flags.data(); }
    std::uint8_t* z_hi() { return flags.data() + at_z_hi(); }
    std::uint8_t* is_basic() { return flags.data() + at_is_basic(); }
    std::uint8_t* want() { return flags.data() + at_want(); }
    std::uint8_t* low() { return flags.data() + at_low(); }
};

// 0, NOT_FINITE or BAD_BOUNDS (boxed.prologue).
int prologue(Mat<const double> M, const double* q, const double* lo, const double* hi);

// The box LCP's checks (box_check, check_scales, check_scales_kept, coupled_check,
// friction_check, is_ray): certify.hpp, the acceptance module (included above).

// The point of a basis (zb basic, zh at hi) into z (boxed.basis_point); false when the
// block is singular or the point not finite.
// `kept`: M's entry in the kept matrices (linalg.equilibrate_finite_kept), the block
// solved by solve_gathered_kept (the same bits); nullptr: solve_gathered.
bool basis_point(Mat<const double> M, const double* q, const double* lo, const double* hi,
                 const std::uint8_t* zb, const std::uint8_t* zh, bool warm_rule, double* z,
                 KeptMatrix* kept = nullptr);

// The point of an extended problem's basis (zb basic, zh at hi: N = n + 2 nf flags, extend's
// variables) solved on the caller's n rows (boxed.friction_point): each row one equation read
// from its variables' states, as _blcp._caller_point reads them (an ordinary row w_i = 0
// when z_i is basic or free, else z_i at its bound by basis_point's warm rule; a friction row
// z_i = +-mu z_f when λ and one of β+, β- are basic, z_i = 0 when neither is, else w_i = 0),
// a sliding row's z_i substituted into its normal's column: one block of the w_i = 0 rows,
// the LCP's size, no extended matrix. F: the friction rows, then their normal rows (2 nf,
// extend's F). False where the extended block is singular by its pattern (λ basic with β+
// and β- at 0; β+ and β- both basic with λ at 0), the block singular or z not finite.
bool friction_point(Mat<const double> M, const double* q, const double* lo, const double* hi,
                    const idx* F, idx nf, const std::uint8_t* zb, const std::uint8_t* zh,
                    double* z);

// The extended box LCP of a friction index into work (FrontLayout's work: Mx, qx, lox, hix),
// F (2 nf) the friction rows then their normal rows (boxed.extend).
void extend(Mat<const double> M, const double* q, const double* lo, const double* hi,
            const idx* findex, idx nf, double* work, idx* F);

// One run, checked (boxed.solve): warm 2n flags, buf BoxLayout(n).length(), final n;
// cov_mode 0, 1 or 2, plus PARTIAL to keep a singular warm basis in part. `checked`: M, q,
// lo, hi are extend's problem, made from data that front's prologue passed (not checked
// again).
SolveResult solve(Mat<const double> M, const double* q, const double* lo, const double* hi,
                  const std::uint8_t* warm, int cov_mode, idx max_pivots, double pivot_tol,
                  double tie_tol, double tol, double* buf, idx* final, bool checked = false);

// The kernel part of solve_blcp with a friction index and/or a warm start (boxed.front):
// returns the code, residual in `residual`. findex_len is 0 or n (the binding checks);
// the other lengths (FrontLayout's) are checked here as the kernel checks them.
int front(int phase, Mat<const double> M, const double* q, const double* lo, const double* hi,
          const idx* findex, idx findex_len, const std::uint8_t* warm, idx warm_len,
          bool has_warm, double tol, double* buf, idx buf_len, idx* ints, idx ints_len,
          double* work, idx work_len, double& residual);

// The thread's workspace (the engine's, boxed.cpp; certify.cpp's box checks take their
// scratch from its check_area).
BoxedWork& thread_work();

// --- helpers of the engine and of its check (certify.cpp) ---

// Whether x[:n] has a non-zero entry (a NaN counts).
inline bool nonzero(const double* x, idx n) {
    for (idx i = 0; i < n; ++i)
        if (x[i] != 0.0) return true;
    return false;
}

// 1 / c into r when c is a power of two whose reciprocal is a normal double (then x * r is
// x / c bit for bit: both round the same exact number once); false otherwise.
inline bool pow2_reciprocal(double c, double& r) {
    std::int64_t b = float_bits(c);
    std::int64_t e = b >> 52;  // the biased exponent (sign 0)
    if ((b & 0xFFFFFFFFFFFFFLL) != 0 || e < 1 || e > 2045) return false;
    r = bits_float((2046 - e) << 52);
    return true;
}

// x / c, by a multiplication where that is exact (pow2_reciprocal): the same bits.
inline double div_exact(double x, double c) {
    double r;
    return pow2_reciprocal(c, r) ? x * r : x / c;
}

// Each row's M z and size, the size of M p: two rows at a time (dot_and_size_lanes2, the
// same bits as row_dot_and_size), inlined into box_check_in's clones.
LEMKE_ALWAYS_INLINE void pair_rows(Mat<const double> M, const double* y, idx i, double* mz,
                                   double* size) {
    idx n = M.rows;
    if (i + 1 < n) {
        double pair[4];
        dot_and_size_lanes2(M.row(i), M.row(i + 1), y, n, pair);
        mz[0] = pair[0];
        mz[1] = pair[1];
        size[0] = pair[2];
        size[1] = pair[3];
    } else {
        dot_and_size_lanes(M.row(i), y, n, mz[0], size[0]);
    }
}

}  // namespace boxed
}  // namespace lemke
