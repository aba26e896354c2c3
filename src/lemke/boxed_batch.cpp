#include "boxed_batch.hpp"

#include <algorithm>
#include <vector>

#include "ladder.hpp"

namespace lemke {
namespace boxed {

namespace {

// One thread's scratch, reused from island to island (grown, never shrunk).
struct Scratch {
    std::vector<double> work, z, w;
    std::vector<std::uint8_t> warm, warm2, cold, zb, zh;
    std::vector<std::int8_t> s;
};

Scratch& scratch() {
    thread_local Scratch s;
    return s;
}

template <class T>
T* sized(std::vector<T>& v, idx len) {
    if (static_cast<idx>(v.size()) < len + 1) v.resize(static_cast<std::size_t>(len + 1));
    return v.data();
}

// The extended variable of each role of friction row of rank r (extend's layout): beta+ is
// the row itself, beta- n + r, lambda n + nf + r.
// Row states -> the kernel's 2N flags (basic, then non-basic at hi).
// (Every one of the N variables is set once, both of its flags, without branches: the
// states follow the data, and branching on them mispredicted from row to row.)
void flags_of(const std::int8_t* c, idx n, idx nf, std::uint8_t* f) {
    idx N = n + 2 * nf;
    auto set = [&](idx j, int s) {
        f[j] = static_cast<std::uint8_t>(s == 2);
        f[N + j] = static_cast<std::uint8_t>(s == 1);
    };
    // a friction code's three digits (base 3: beta+, beta-, lambda), looked up rather than
    // divided out (the divisions' chain was most of this loop)
    struct Digits {
        std::uint8_t d[27][3];
        constexpr Digits() : d{} {
            for (int e = 0; e < 27; ++e) {
                d[e][0] = static_cast<std::uint8_t>(e / 9);
                d[e][1] = static_cast<std::uint8_t>((e / 3) % 3);
                d[e][2] = static_cast<std::uint8_t>(e % 3);
            }
        }
    };
    static constexpr Digits digits{};
    idx r = 0;
    for (idx i = 0; i < n; ++i) {
        int e = c[i];
        if (e >= FRICTION_STATE) {
            const std::uint8_t* d = digits.d[e - FRICTION_STATE];
            set(i, d[0]);
            set(n + r, d[1]);
            set(n + nf + r, d[2]);
            ++r;
        } else {
            set(i, e);
        }
    }
}

// A final basis (final[:k] basic, final[k:m] at hi) -> row states; `fric` says which rows
// are friction rows (nullptr: none).
void states_of(const idx* final, idx k, idx m, idx n, idx nf, const idx* findex,
               std::int8_t* s_ext, std::int8_t* c) {
    idx N = n + 2 * nf;
    std::fill(s_ext, s_ext + N, std::int8_t(0));
    for (idx t = 0; t < k; ++t) s_ext[final[t]] = 2;
    for (idx t = k; t < m; ++t) s_ext[final[t]] = 1;
    idx r = 0;
    for (idx i = 0; i < n; ++i) {
        if (findex != nullptr && findex[i] >= 0) {
            c[i] = static_cast<std::int8_t>(FRICTION_STATE + 9 * s_ext[i] + 3 * s_ext[n + r] +
                                            s_ext[n + nf + r]);
            ++r;
        } else {
            c[i] = s_ext[i];
        }
    }
}

struct Outcome {
    int code = 0;
    idx pivots = 0, k = 0, m = 0, rec = 0;
    int stage = -1;
    double residual = INF;
};

// _blcp._one_call for one island (see its docstring), the same kernel calls in the same order.
Outcome one_call(Mat<const double> M, const double* q, const double* lo, const double* hi,
                 const idx* fi, idx fl, const std::uint8_t* warm, bool has_warm, idx nf,
                 idx limit, double pt, double tt, double tol, double* buf, idx buf_len,
                 idx* ints, idx ints_len, Scratch& S) {
    Outcome o;
    idx n = M.rows;
    bool friction = fl > 0;
    FrontLayout FL{n, nf, friction};
    BoxLayout L = FL.run();
    idx N = FL.N();
    idx work_len = FL.work_length();
    double* work = sized(S.work, work_len);
    double residual;
    int code = front(PREPARE, M, q, lo, hi, fi, fl, warm, 2 * N, has_warm, tol, buf, buf_len,
                     ints, ints_len, work, work_len, residual);
    if (code == 0) {
        o.code = 0;
        o.stage = 0;
        o.pivots = 0;
        o.residual = residual;
        return o;
    }
    if (code != NEED_RUN) {
        o.stage = code == UNDECIDED ? -1 : -2;
        return o;
    }
    Mat<const double> A = M;
    const double *qa = q, *la = lo, *ha = hi;
    if (nf > 0) {
        A = Mat<const double>(work + FL.work_M(), N, N);
        qa = work + FL.work_q();
        la = work + FL.work_lo();
        ha = work + FL.work_hi();
    }
    double* ext = buf;  // the run's BoxLayout(N)
    idx* final = ints + FL.final();
    bool xp = nf > 0;  // (extend's problem: its data passed front's prologue)
    idx pivots = 0, rec = 0;
    // A run that ended solved and checked: with a friction index, the check on the
    // caller's data decides (front's SOLVED_RUN phase; failed: the general path).
    auto solved = [&](const SolveResult& run, idx piv, idx recs, double res, bool from_warm) {
        if (friction && front(SOLVED_RUN, M, q, lo, hi, fi, fl, warm, 2 * N, from_warm, tol,
                              buf, buf_len, ints, ints_len, work, work_len, res) != 0)
            return o;
        Outcome s;
        s.stage = 1;
        s.pivots = piv;
        s.k = run.k;
        s.m = run.m;
        s.rec = recs;
        s.residual = res;
        return s;
    };
    // The ladder (ladder.hpp): the warm start's basis, the same with its friction rows cold,
    // cold, then the other covering vectors and exact ties; the first run solved and checked
    // settles it, a checked ray (left to the general path) or a stop (TIME_LIMIT,
    // INTERRUPTED) in any rung ends it, as in _blcp._one_call: no rung runs after a stop (an
    // interrupt is seen by the run it hits only: a later rung's fresh run would go on, and
    // Ctrl-C would wait for the whole ladder).
    SolveResult r;
    ladder::Cap cap{limit, 0};
    bool ok = false, ended = false;
    auto go = [&](const std::uint8_t* flags, int mode, idx left, double tie) {
        r = solve(A, qa, la, ha, flags, mode, left, pt, tie, tol, ext, final, xp);
        cap.charge(r.pivots);
        ok = r.code == 0 && r.ok;
        residual = r.residual;
    };
    std::uint8_t* cold = nullptr;
    int solved_by = ladder::climb(
        [&] { return ok || ended || is_stop(r.code); },
        ladder::rung("the warm start's basis", [&] { return has_warm; }, [&] {
            go(warm, 1 | PARTIAL, cap.left(), tt);
            if (!ok) {  // _checked_point: the point of the final basis, recomputed and judged
                std::uint8_t* zb = sized(S.zb, N);
                std::uint8_t* zh = sized(S.zh, N);
                std::fill(zb, zb + N, std::uint8_t(0));
                std::fill(zh, zh + N, std::uint8_t(0));
                for (idx t = 0; t < r.k; ++t) zb[final[t]] = 1;
                for (idx t = r.k; t < r.m; ++t) zh[final[t]] = 1;
                double* z = sized(S.z, N);
                if (basis_point(A, qa, la, ha, zb, zh, false, z)) {
                    double* w = sized(S.w, N);
                    double res2;
                    if (box_check(A, qa, la, ha, z, tol, w, ext + L.row_scale(), 0, res2)) {
                        ok = true;
                        std::copy(z, z + N, ext + L.z());
                        std::copy(w, w + N, ext + L.w());
                        residual = res2;
                    }
                }
            }
            if (!ok) rec = 1;
        }),
        ladder::rung("its friction rows cold (_blcp._reset)",
                     [&] { return has_warm && nf > 0; }, [&] {
            std::uint8_t* warm2 = sized(S.warm2, 2 * N);
            std::copy(warm, warm + 2 * N, warm2);
            const idx* F = ints + FL.friction_rows();
            for (idx c = 0; c < nf; ++c) {
                const idx vars[3] = {F[c], n + c, n + nf + c};
                for (idx v : vars) warm2[v] = warm2[N + v] = 0;
            }
            go(warm2, 1 | PARTIAL, cap.left_or_0(), tt);
            if (!ok) rec = 2;
        }),
        ladder::rung("cold", ladder::Always{}, [&] {
            cold = sized(S.cold, 2 * N);
            std::fill(cold, cold + 2 * N, std::uint8_t(0));
            go(cold, 0, cap.left_or_0(), tt);
            ended = !ok && r.code == RAY_TERMINATION &&
                    is_ray(A, qa, la, ha, ext + L.covering(), ext + L.z(), r.z0, ext + L.ray(),
                           tol);  // (the general path reports the ray)
        }),
        ladder::rung("other covering vectors", [&] { return cap.left() > 0; }, [&] {
            go(cold, 1, cap.left(), tt);
            ++rec;
        }),
        ladder::rung("exact ties", [&] { return cap.left() > 0; }, [&] {
            go(cold, 2, cap.left(), 0.0);
            ++rec;
        }));
    if (!ok) return o;
    pivots = cap.pivots;
    return solved(r, pivots, rec, residual, solved_by < 2);
}

}  // namespace

void row_states(const idx* final, idx k, idx m, idx n, idx nf, const idx* findex,
                std::int8_t* scratch, std::int8_t* states) {
    states_of(final, k, m, n, nf, findex, scratch, states);
}

void batch(const double* Ms, const idx* mstart, const double* qs, const double* los,
           const double* his, const idx* qoff, const idx* findex, const std::uint8_t* fflag,
           const std::int8_t* state, const std::uint8_t* wflag, idx lo, idx hi,
           const idx* max_pivots, double pivot_tol, double tie_tol, double tol, double* bufs,
           const idx* buff, idx* ints, const idx* ioff, std::int8_t* state_out, idx* out_i,
           double* out_f) {
    Scratch& S = scratch();
    for (idx b = lo; b < hi; ++b) {
        idx o = qoff[b], n = qoff[b + 1] - o;
        Mat<const double> M(Ms + mstart[b], n, n);
        const double *q = qs + o, *l = los + o, *h = his + o;
        bool has_f = fflag[b] != 0, has_w = wflag[b] != 0;
        const idx* fi = has_f ? findex + o : nullptr;
        idx nf = 0;
        if (has_f)
            for (idx i = 0; i < n; ++i) nf += fi[i] >= 0;
        idx N = n + 2 * nf;
        double* buf = bufs + buff[b];
        idx* in = ints + ioff[b];
        Outcome r;
        if (!has_f && !has_w) {  // solve_blcp's cold fast path: one run
            std::uint8_t* cold = sized(S.cold, 2 * n);
            std::fill(cold, cold + 2 * n, std::uint8_t(0));
            SolveResult s = solve(M, q, l, h, cold, 0, max_pivots[b], pivot_tol, tie_tol, tol,
                                  buf, in);
            r.code = s.code;
            if (s.code == 0 && s.ok) {
                r.stage = 1;
                r.pivots = s.pivots;
                r.k = s.k;
                r.m = s.m;
                r.residual = s.residual;
            } else {
                r.stage = (s.code == NOT_FINITE || s.code == BAD_BOUNDS) ? -2 : -1;
            }
        } else {
            std::uint8_t* warm = sized(S.warm, 2 * N);
            if (has_w) flags_of(state + o, n, nf, warm);
            else std::fill(warm, warm + 2 * N, std::uint8_t(0));
            idx fl = has_f && n > 0 ? n : 0;
            r = one_call(M, q, l, h, fl ? fi : findex, fl, warm, has_w, nf, max_pivots[b],
                         pivot_tol, tie_tol, tol, buf, buff[b + 1] - buff[b], in,
                         ioff[b + 1] - ioff[b], S);
        }
        std::int8_t* so = state_out + o;
        if (r.stage == 0) {
            std::copy(state + o, state + o + n, so);
        } else if (r.stage == 1) {
            std::int8_t* s_ext = sized(S.s, N);
            states_of(in, r.k, r.m, n, nf, fi, s_ext, so);
        }
        idx* oi = out_i + 7 * b;
        oi[0] = r.code;
        oi[1] = r.pivots;
        oi[2] = r.k;
        oi[3] = r.m;
        oi[4] = r.rec;
        oi[5] = r.stage;
        oi[6] = N;
        out_f[b] = r.residual;
    }
}

}  // namespace boxed
}  // namespace lemke
