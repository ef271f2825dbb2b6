/*
 * rotorkit's adaptive explicit Runge-Kutta loop in C99: the port of
 * rotorkit/engines/rk_numba.py's _rk_loop and its helpers, step by step and
 * in the same order of arithmetic, so that it takes the same steps (nfev,
 * accepted, rejected) and gives the same samples to rounding.
 *
 * This file is a template: rotorkit.engines.rk_c replaces the GENERATED
 * marker below with the statuses, controller constants and scipy's
 * coefficient tables of rotorkit/engines/rk_common.py (C literals with
 * repr() precision: the same doubles), and builds it with
 * rotorkit.codegen.cbuild. One source of truth for the numbers.
 *
 * Exported:
 *
 *   int64_t rk_integrate(rk_core core, int64_t method, double t0, double t1,
 *                        const double *y0, int64_t n, const double *p,
 *                        const double *t_eval, int64_t n_eval, double rtol,
 *                        const double *atol, double first_step, double max_step,
 *                        int64_t max_steps, int64_t pause_after,
 *                        double *samples, int64_t columns, double *y_out,
 *                        int64_t *counters_out, double *reals_out);
 *
 * core        right-hand side: core(t, y, p, dydt) writes all n entries of dydt
 * method      METHOD_RK45 (0) or METHOD_DOP853 (1)
 * y0, atol    n entries; p as the core expects it; t_eval n_eval sorted times in [t0, t1]
 * first_step  <= 0: scipy's heuristic picks it
 * max_steps   most step attempts (accepted + rejected)
 * pause_after return (STATUS_PAUSED) after this many accepted steps; 0: never
 * samples     n x columns, row-major (numba's (n_states, columns) array); columns <= n_eval:
 *             the run also pauses, between two steps, when the next step might sample past it
 * y_out       n entries: the state at t_reached
 * counters_out  {n_samples_done, nfev, n_accepted, n_rejected}
 * reals_out     {t_reached, h_next}
 *
 * Returns the status: STATUS_SUCCESS 0, STATUS_STEP_TOO_SMALL -1,
 * STATUS_NON_FINITE -2, STATUS_MAX_STEPS -3, STATUS_PAUSED -4,
 * STATUS_NO_MEMORY -5 (malloc of the scratch arrays failed: nothing was
 * integrated, samples and y_out untouched), STATUS_BAD_ARGUMENT -6 (a null core, n < 1, an unknown
 * method, columns outside [0, n_eval]: the Python front end never passes
 * these).
 *
 * No global state: scratch memory is allocated per call and freed before
 * returning, so concurrent calls (threads: ctypes releases the GIL) are
 * independent. Build with ISO C99 floating point (no -ffast-math, no FMA
 * contraction: gcc's -std=c99 default) to round like numba's code.
 */

#if defined(__GNUC__) && !defined(__clang__)
/* gcc: vectorise the loops over the state (-O2's "very cheap" cost model leaves them scalar; vectorising
 * element-wise loops does not change a result, and reductions stay in order without -ffast-math); never fuse
 * a multiply and an add, whatever the flags (numba does not either) */
#pragma GCC optimize("O3", "fp-contract=off")
#endif

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

typedef void (*rk_core)(double t, const double *y, const double *p, double *dydt);

/* @GENERATED@ */

#define STATUS_RUNNING 1

/* The helpers are inlined into rk_integrate, which gcc on x86-64 Linux builds twice, for any x86-64 and for
 * AVX2 (4 doubles a vector: the stage sums run ~2x faster on large states), the loader picking the one the
 * processor runs (an ifunc): one library for every machine that shares the cache. Same arithmetic in both
 * (RK_ONE_VERSION defined: only the first, as the tests build it to compare). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) \
    && !defined(RK_ONE_VERSION)
#define RK_VERSIONS __attribute__((target_clones("default", "avx2")))
#else
#define RK_VERSIONS
#endif
#if defined(__GNUC__)
#define RK_HELPER static inline __attribute__((always_inline))
#else
#define RK_HELPER static inline
#endif

/* ------------------------------------------------------------------------- */
/* Helpers (rk_numba's @njit kernels)                                        */
/* ------------------------------------------------------------------------- */

RK_HELPER int all_finite(const double *x, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

RK_HELPER int all_finite_and_bounded(const double *x, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(x[i]) || fabs(x[i]) > DIVERGED)
            return 0;
    return 1;
}

/* out = sum(weights[j] * rows[j] for j < n_terms), rows of length n; zero weights skipped */
RK_HELPER void weighted_sum(const double *restrict rows, const double *restrict weights, int64_t n_terms,
                         double *restrict out, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        out[i] = 0.0;
    for (int64_t j = 0; j < n_terms; j++) {
        const double w = weights[j];
        if (w != 0.0) {
            const double *restrict row = rows + j * n;
            for (int64_t i = 0; i < n; i++)
                out[i] += row[i] * w;
        }
    }
}

/* RMS norm of x / scale as scipy's norm computes it */
RK_HELPER double rms(const double *x, const double *scale, int64_t n)
{
    double acc = 0.0;
    for (int64_t i = 0; i < n; i++) {
        const double v = x[i] / scale[i];
        acc += v * v;
    }
    return sqrt(acc) / sqrt((double)n); /* numba's x.size ** 0.5 is LLVM's sqrt, not libm's pow */
}

/* atol + rtol * max(|y|, |y_new|) */
RK_HELPER void error_scale(const double *y, const double *y_new, double rtol, const double *atol, double *out,
                        int64_t n)
{
    for (int64_t i = 0; i < n; i++) {
        const double a = fabs(y[i]), b = fabs(y_new[i]);
        out[i] = atol[i] + (b > a ? b : a) * rtol;
    }
}

/* scipy's select_initial_step (forward direction, one evaluation) */
RK_HELPER double select_initial_step(rk_core core, double t0, const double *y0, const double *f0, const double *p,
                                  double t1, double max_step, int64_t order, double rtol, const double *atol,
                                  double *y1, double *f1, double *scale, int64_t n)
{
    const double interval_length = fabs(t1 - t0);
    if (interval_length == 0.0)
        return 0.0;
    for (int64_t i = 0; i < n; i++)
        scale[i] = atol[i] + fabs(y0[i]) * rtol;
    const double d0 = rms(y0, scale, n);
    const double d1 = rms(f0, scale, n);
    double h0;
    if (d0 < 1e-5 || d1 < 1e-5)
        h0 = 1e-6;
    else
        h0 = 0.01 * d0 / d1;
    if (interval_length < h0) /* Python's min(h0, interval_length): a NaN h0 stays */
        h0 = interval_length;
    for (int64_t i = 0; i < n; i++)
        y1[i] = y0[i] + h0 * f0[i];
    core(t0 + h0, y1, p, f1);
    for (int64_t i = 0; i < n; i++)
        y1[i] = f1[i] - f0[i];
    const double d2 = rms(y1, scale, n) / h0;
    double h1;
    if (d1 <= 1e-15 && d2 <= 1e-15) {
        const double small = h0 * 1e-3;
        h1 = small > 1e-6 ? small : 1e-6;
    } else {
        const double d_max = d2 > d1 ? d2 : d1; /* a NaN candidate is ignored */
        h1 = pow(0.01 / d_max, 1.0 / (double)(order + 1));
    }
    double h = 100.0 * h0;
    if (h1 < h)
        h = h1;
    if (interval_length < h)
        h = interval_length;
    if (max_step < h)
        h = max_step;
    return h;
}

/* One explicit RK step; k[0] holds f(t, y) on entry. Fills k[1..n_stages-1], y_new and
 * k[n_stages] = f(t + h, y_new). Returns the evaluations made; *ok = 0 when a stage, the new
 * state or its derivative is not finite (or the state diverged): the step stops there. */
RK_HELPER int64_t rk_step(rk_core core, double t, const double *y, double h, const double *p, const double *a,
                       int64_t a_stride, const double *b, const double *c, int64_t n_stages, double *k,
                       double *y_new, double *y_stage, double *work, int64_t n, int *ok)
{
    for (int64_t s = 1; s < n_stages; s++) {
        weighted_sum(k, a + s * a_stride, s, work, n);
        for (int64_t i = 0; i < n; i++)
            y_stage[i] = y[i] + work[i] * h;
        core(t + c[s] * h, y_stage, p, k + s * n);
        if (!all_finite(k + s * n, n)) {
            *ok = 0;
            return s;
        }
    }
    weighted_sum(k, b, n_stages, work, n);
    for (int64_t i = 0; i < n; i++)
        y_new[i] = y[i] + h * work[i];
    if (!all_finite_and_bounded(y_new, n)) {
        *ok = 0;
        return n_stages - 1;
    }
    core(t + h, y_new, p, k + n_stages * n);
    if (!all_finite(k + n_stages * n, n)) {
        *ok = 0;
        return n_stages;
    }
    *ok = 1;
    return n_stages;
}

/* scipy's RK45 error norm: norm(h * K.T @ E / scale) */
RK_HELPER double rk45_error_norm(const double *k, double h, const double *scale, double *work, int64_t n)
{
    weighted_sum(k, RK45_E, RK45_N_STAGES + 1, work, n);
    for (int64_t i = 0; i < n; i++)
        work[i] *= h;
    return rms(work, scale, n);
}

/* scipy's DOP853 error norm blending the 5th- and 3rd-order estimates */
RK_HELPER double dop853_error_norm(const double *k, double h, const double *scale, double *work5, double *work3,
                                int64_t n)
{
    weighted_sum(k, DOP853_E5, DOP853_N_STAGES + 1, work5, n);
    weighted_sum(k, DOP853_E3, DOP853_N_STAGES + 1, work3, n);
    double err5_sq = 0.0, err3_sq = 0.0;
    for (int64_t i = 0; i < n; i++) {
        const double v5 = work5[i] / scale[i];
        const double v3 = work3[i] / scale[i];
        err5_sq += v5 * v5;
        err3_sq += v3 * v3;
    }
    if (err5_sq == 0.0 && err3_sq == 0.0)
        return 0.0;
    const double denom = err5_sq + 0.01 * err3_sq;
    return fabs(h) * err5_sq / sqrt(denom * (double)n);
}

/* RK45 dense-output weights q[j] = (K.T @ P)[:, j] of the last step */
RK_HELPER void rk45_dense_prepare(const double *k, double *q, int64_t n)
{
    for (int64_t j = 0; j < RK45_DENSE_ROWS; j++)
        weighted_sum(k, RK45_PT[j], RK45_N_STAGES + 1, q + j * n, n);
}

/* quartic interpolant at t into column col of out (n x columns) */
RK_HELPER void rk45_dense_eval(const double *q, const double *y_old, double t_old, double h, double t, double *out,
                            int64_t columns, int64_t col, int64_t n)
{
    const double x = (t - t_old) / h;
    const double p1 = x;
    const double p2 = p1 * x;
    const double p3 = p2 * x;
    const double p4 = p3 * x;
    for (int64_t i = 0; i < n; i++) {
        const double acc = q[i] * p1 + q[n + i] * p2 + q[2 * n + i] * p3 + q[3 * n + i] * p4;
        out[i * columns + col] = h * acc + y_old[i];
    }
}

/* DOP853: three extra stages and the 7 interpolant rows f of the last step; returns the
 * evaluations made, *ok = 0 when an extra stage is not finite */
RK_HELPER int64_t dop853_dense_prepare(rk_core core, double t_old, double h, const double *y_old,
                                    const double *y_new, const double *p, double *k, double *f, double *y_stage,
                                    double *work, int64_t n, int *ok)
{
    const int64_t n_base = DOP853_N_STAGES + 1;
    for (int64_t s = n_base; s < DOP853_N_STAGES_EXTENDED; s++) {
        weighted_sum(k, DOP853_A[s], s, work, n);
        for (int64_t i = 0; i < n; i++)
            y_stage[i] = y_old[i] + work[i] * h;
        core(t_old + DOP853_C[s] * h, y_stage, p, k + s * n);
        if (!all_finite(k + s * n, n)) {
            *ok = 0;
            return s - n_base + 1;
        }
    }
    const double *f_old = k;
    const double *f_new = k + DOP853_N_STAGES * n;
    for (int64_t i = 0; i < n; i++) {
        const double delta = y_new[i] - y_old[i];
        f[i] = delta;
        f[n + i] = h * f_old[i] - delta;
        f[2 * n + i] = 2.0 * delta - h * (f_new[i] + f_old[i]);
    }
    for (int64_t r = 0; r < DOP853_DENSE_ROWS; r++) {
        weighted_sum(k, DOP853_D[r], DOP853_N_STAGES_EXTENDED, work, n);
        for (int64_t i = 0; i < n; i++)
            f[(3 + r) * n + i] = h * work[i];
    }
    *ok = 1;
    return DOP853_N_STAGES_EXTENDED - n_base;
}

/* 7th-order interpolant at t into column col of out (n x columns) */
RK_HELPER void dop853_dense_eval(const double *f, const double *y_old, double t_old, double h, double t, double *out,
                              int64_t columns, int64_t col, int64_t n)
{
    const double x = (t - t_old) / h;
    const int64_t n_rows = DOP853_INTERPOLATOR_POWER;
    for (int64_t i = 0; i < n; i++) {
        double acc = 0.0;
        for (int64_t r = 0; r < n_rows; r++) {
            acc += f[(n_rows - 1 - r) * n + i];
            if (r % 2 == 0)
                acc *= x;
            else
                acc *= 1.0 - x;
        }
        out[i * columns + col] = acc + y_old[i];
    }
}

RK_HELPER void copy_column(const double *src, double *out, int64_t columns, int64_t col, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        out[i * columns + col] = src[i];
}

/* scipy's step-size factor for an error norm (accepted or not) */
RK_HELPER double step_factor(double error_norm, double error_exponent, int rejected_before)
{
    double factor;
    if (error_norm < 1.0) {
        if (error_norm == 0.0) {
            factor = MAX_FACTOR;
        } else {
            factor = SAFETY * pow(error_norm, error_exponent);
            if (!(factor < MAX_FACTOR))
                factor = MAX_FACTOR;
        }
        if (rejected_before && factor > 1.0)
            factor = 1.0;
        return factor;
    }
    factor = SAFETY * pow(error_norm, error_exponent);
    if (!(factor > MIN_FACTOR)) /* also catches NaN, like Python's max() */
        factor = MIN_FACTOR;
    return factor;
}

/* ------------------------------------------------------------------------- */
/* The loop (rk_numba._rk_loop)                                              */
/* ------------------------------------------------------------------------- */

RK_VERSIONS
int64_t rk_integrate(rk_core core, int64_t method, double t0, double t1, const double *y0, int64_t n,
                     const double *p, const double *t_eval, int64_t n_eval, double rtol, const double *atol,
                     double first_step, double max_step, int64_t max_steps, int64_t pause_after, double *samples,
                     int64_t columns, double *y_out, int64_t *counters_out, double *reals_out)
{
    counters_out[0] = counters_out[1] = counters_out[2] = counters_out[3] = 0;
    reals_out[0] = t0;
    reals_out[1] = NAN;
    if (core == NULL || n < 1 || n_eval < 0 || columns < 0 || columns > n_eval
        || (method != METHOD_RK45 && method != METHOD_DOP853))
        return STATUS_BAD_ARGUMENT;

    const double *a, *b, *c;
    int64_t a_stride, n_stages, n_rows, error_order;
    if (method == METHOD_RK45) {
        a = &RK45_A[0][0];
        a_stride = RK45_N_STAGES + 1;
        b = RK45_B;
        c = RK45_C;
        n_stages = RK45_N_STAGES;
        n_rows = RK45_N_STAGES + 1;
        error_order = RK45_ERROR_ORDER;
    } else {
        a = &DOP853_A[0][0];
        a_stride = DOP853_N_STAGES_EXTENDED;
        b = DOP853_B;
        c = DOP853_C;
        n_stages = DOP853_N_STAGES;
        n_rows = DOP853_N_STAGES_EXTENDED;
        error_order = DOP853_ERROR_ORDER;
    }
    const double error_exponent = -1.0 / (double)(error_order + 1);

    /* scratch: k (n_rows x n), dense (7 x n), y, y_new, f, y_stage, work, work2, scale */
    const int64_t n_vectors = n_rows + DOP853_INTERPOLATOR_POWER + 7;
    double *memory = NULL;
    if ((uint64_t)n <= SIZE_MAX / sizeof(double) / (uint64_t)n_vectors)
        memory = malloc((size_t)n * (size_t)n_vectors * sizeof(double));
    if (memory == NULL)
        return STATUS_NO_MEMORY; /* nothing integrated, nothing written but the counters (0) and t_reached (t0) */
    double *k = memory; /* stages; row n_stages is f(t_new, y_new) */
    double *dense = k + n_rows * n;
    double *y = dense + DOP853_INTERPOLATOR_POWER * n;
    double *y_new = y + n;
    double *f = y_new + n;
    double *y_stage = f + n;
    double *work = y_stage + n;
    double *work2 = work + n;
    double *scale = work2 + n;
    for (int64_t i = 0; i < n; i++)
        y[i] = y0[i];

    /* samples at t0 are the initial state itself */
    const int64_t capacity = columns; /* == n_eval unless pausing: a step whose samples overflow it is redone later */
    int64_t i_eval = 0;
    while (i_eval < n_eval && i_eval < capacity && t_eval[i_eval] <= t0) {
        copy_column(y0, samples, columns, i_eval, n);
        i_eval++;
    }

    double t = t0;
    int64_t n_accepted = 0, n_rejected = 0;
    int64_t status = STATUS_RUNNING;
    core(t, y, p, f);
    int64_t nfev = 1;
    if (!all_finite(f, n))
        status = STATUS_NON_FINITE;
    double h_abs = first_step;
    if (status == STATUS_RUNNING && first_step <= 0.0) {
        h_abs = select_initial_step(core, t0, y0, f, p, t1, max_step, error_order, rtol, atol, y_stage, work,
                                    scale, n);
        nfev++;
    }

    while (status == STATUS_RUNNING) {
        if (t >= t1) {
            status = STATUS_SUCCESS;
            break;
        }
        if (pause_after > 0 && n_accepted >= pause_after) {
            status = STATUS_PAUSED; /* between two steps: nothing of the controller's state is lost */
            break;
        }
        const double min_step = 10.0 * fabs(nextafter(t, INFINITY) - t);
        if (capacity < n_eval) {
            /* the next step ends at most at t + its first attempt (clipped to [min_step, max_step]) */
            double reach = max_step < h_abs ? max_step : h_abs;
            if (min_step > reach)
                reach = min_step;
            if (t_eval[capacity] <= t + reach) {
                status = STATUS_PAUSED; /* it might sample past the buffer */
                break;
            }
        }

        /* --- one accepted step (scipy's _step_impl) --- */
        if (h_abs > max_step)
            h_abs = max_step;
        else if (h_abs < min_step)
            h_abs = min_step;
        int rejected = 0, non_finite = 0;
        double t_new = t, h = 0.0;
        for (;;) {
            if (!(h_abs >= min_step)) { /* also stops on a NaN step size */
                status = non_finite ? STATUS_NON_FINITE : STATUS_STEP_TOO_SMALL;
                break;
            }
            if (n_accepted + n_rejected >= max_steps) {
                status = STATUS_MAX_STEPS;
                break;
            }
            t_new = t + h_abs;
            if (t_new > t1)
                t_new = t1;
            h = t_new - t;
            h_abs = fabs(h);

            for (int64_t i = 0; i < n; i++)
                k[i] = f[i];
            int ok;
            nfev += rk_step(core, t, y, h, p, a, a_stride, b, c, n_stages, k, y_new, y_stage, work, n, &ok);
            if (!ok) { /* non-finite stage: retry with a smaller step */
                non_finite = 1;
                rejected = 1;
                n_rejected++;
                h_abs *= MIN_FACTOR;
                continue;
            }
            non_finite = 0;

            error_scale(y, y_new, rtol, atol, scale, n);
            double error_norm;
            if (method == METHOD_RK45)
                error_norm = rk45_error_norm(k, h, scale, work, n);
            else
                error_norm = dop853_error_norm(k, h, scale, work, work2, n);
            h_abs *= step_factor(error_norm, error_exponent, rejected);
            if (error_norm < 1.0)
                break;
            rejected = 1;
            n_rejected++;
        }
        if (status != STATUS_RUNNING)
            break;
        n_accepted++;

        /* --- samples inside (t, t_new] from the step's dense output --- */
        if (i_eval < n_eval && t_eval[i_eval] <= t_new) {
            if (method == METHOD_RK45) {
                rk45_dense_prepare(k, dense, n);
            } else {
                int ok;
                nfev += dop853_dense_prepare(core, t, h, y, y_new, p, k, dense, y_stage, work, n, &ok);
                if (!ok) { /* keep t, y at the last step fully sampled */
                    status = STATUS_NON_FINITE;
                    break;
                }
            }
            /* i_eval < capacity always holds here (the pause check above); kept as a guard for memory safety */
            while (i_eval < n_eval && i_eval < capacity && t_eval[i_eval] <= t_new) {
                const double t_sample = t_eval[i_eval];
                if (t_sample == t_new)
                    copy_column(y_new, samples, columns, i_eval, n);
                else if (method == METHOD_RK45)
                    rk45_dense_eval(dense, y, t, h, t_sample, samples, columns, i_eval, n);
                else
                    dop853_dense_eval(dense, y, t, h, t_sample, samples, columns, i_eval, n);
                i_eval++;
            }
        }

        t = t_new;
        double *swap = y;
        y = y_new;
        y_new = swap;
        for (int64_t i = 0; i < n; i++)
            f[i] = k[n_stages * n + i];
    }

    for (int64_t i = 0; i < n; i++)
        y_out[i] = y[i];
    free(memory);
    counters_out[0] = i_eval;
    counters_out[1] = nfev;
    counters_out[2] = n_accepted;
    counters_out[3] = n_rejected;
    reals_out[0] = t;
    reals_out[1] = h_abs;
    return status;
}
