/* ensemble.c: `ensemble K [seed=S] [file=FILE] [summary=FILE]` ... `end`: the body run K times,
 * each replica on a new system of its own with the seed S + r - 1 (r = 1 ... K), on the
 * machine's threads; the measurements the commands give (mote_call_result) combined into a
 * mean and a standard error per quantity.
 *
 * The body is read K times as the script is read (a loop over `replica`), so each replica has
 * its own calls, checked one by one before anything runs. Running, each replica gets a shallow
 * copy of the script with a context of its own (its output into memory, its measurements,
 * one thread) and its own model, on a pool of POSIX threads that take the replicas in turn;
 * the replicas' outputs are then printed in replica order and
 * their measurements combined in that order, so that what an ensemble prints and writes does
 * not depend on the number of threads. */
#include "script_internal.h"
#include "mote/stats.h"
#include "mote/datafile.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

const mote_ensemble *mote_ensemble_at(const mote_script *s, size_t call)
{
    size_t lo = 0, hi = s->nens;
    while (lo < hi) { /* (in the order of their calls) */
        size_t mid = lo + (hi - lo) / 2;
        if (s->ens[mid].call < call)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < s->nens && s->ens[lo].call == call ? &s->ens[lo] : NULL;
}

int mote_ensemble_add(mote_script *s, size_t call, int K, mote_ensemble **out)
{
    if (s->nens == s->capens) {
        size_t cap = s->capens ? 2 * s->capens : 8;
        mote_ensemble *e = realloc(s->ens, cap * sizeof *e);
        if (!e)
            return MOTE_ENOMEM;
        s->ens = e;
        s->capens = cap;
    }
    mote_ensemble *e = &s->ens[s->nens];
    e->call = call;
    e->K = K;
    e->start = mote_arena_alloc(&s->arena, ((size_t)K + 1) * sizeof *e->start);
    if (!e->start)
        return MOTE_ENOMEM;
    s->nens++;
    *out = e;
    return MOTE_OK;
}

/* ---- checking -------------------------------------------------------------------------------- */

int mote_ensemble_check(mote_script *s, const mote_ensemble *e, mote_err *err)
{
    const mote_call *ec = &s->calls[e->call];
    if (!s->model->seed)
        return mote_call_fail(err, ec, -1, MOTE_EINVAL,
                              "ensemble: the %s model draws no random numbers, so its replicas "
                              "would all be the same run", s->model->name);
    const mote_arg *sum = mote_call_opt(ec, "summary");
    if (sum) {
        const char *kind = mote_outputs_find(&s->ctx.outputs, sum->path);
        int rc = mote_outputs_note_path(&s->ctx.outputs, ec, mote_call_opt_index(ec, "summary"),
                                        sum->path, "ensemble-summary",
                                        kind && !strcmp(kind, "ensemble-summary"), err);
        if (rc)
            return rc;
    }
    void *outer = s->instance; /* each replica starts from a new, dry system */
    int rc = 0;
    for (int r = 0; r < e->K && !rc; r++) {
        void *dry = s->model->create(&s->ctx, 1);
        if (!dry)
            return mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
        s->instance = dry;
        for (size_t i = e->start[r]; i < e->start[r + 1] && !rc; i++) {
            mote_call *c = &s->calls[i];
            if (!strcmp(c->name, "live"))
                rc = mote_call_fail(err, c, -1, MOTE_EINVAL, "live: the live view shows one "
                                    "system; start it before the ensemble, not inside it");
            if (!rc)
                rc = mote_script_check_call(s, c, err);
        }
        s->model->destroy(s->instance); /* (`reset` may have replaced it) */
    }
    s->instance = outer;
    return rc;
}

/* ---- running --------------------------------------------------------------------------------- */

typedef struct {
    mote_script s;        /* a shallow copy: its own context, model and measurements */
    mote_results res;
    char *out, *diag;     /* what the replica printed */
    size_t nout, ndiag;
    mote_err err;
    int rc;
} replica;

/* Ctrl-C in an ensemble: the script's own thread asks the context's interrupt hook (Python's
 * signal handlers run there alone), and every replica then stops at its next safe point. */
typedef struct {
    atomic_int stop;
    pthread_t main;
    int (*hook)(void *arg);
    void *arg;
} ens_stop;

static int ens_interrupt(void *arg)
{
    ens_stop *st = arg;
    if (st->hook && pthread_equal(pthread_self(), st->main) && st->hook(st->arg))
        atomic_store(&st->stop, 1);
    return atomic_load(&st->stop);
}

static void run_replica(mote_script *s, const mote_ensemble *e, int r, replica *rp, int solo,
                        ens_stop *st)
{
    FILE *out = open_memstream(&rp->out, &rp->nout), *diag = open_memstream(&rp->diag, &rp->ndiag);
    rp->s = *s;
    mote_context *ctx = &rp->s.ctx;
    memset(&ctx->outputs, 0, sizeof ctx->outputs);
    ctx->npending_dirs = 0;
    ctx->out = out;
    ctx->diag = diag;
    ctx->terminal = 0;
    ctx->tick = NULL;
    ctx->interrupt = ens_interrupt;
    ctx->interrupt_arg = st;
    ctx->report = NULL; /* (the ensemble reports its replicas done) */
    ctx->threads = 1; /* (the replicas are the threads) */
    ctx->results = &rp->res;
    ctx->ranks = NULL; /* (under mpirun a replica runs in one rank: solo) */
    ctx->solo = solo;
    rp->s.live = NULL;
    rp->s.threads_noted = 1;
    const mote_call *ec = &s->calls[e->call];
    const mote_arg *seed = mote_call_opt(ec, "seed");
    void *model = out && diag ? s->model->create(ctx, 0) : NULL;
    if (!model) {
        rp->rc = mote_call_fail(&rp->err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
    } else {
        rp->s.instance = model;
        s->model->seed(model, (seed ? seed->u : 1) + (uint64_t)r);
        rp->rc = mote_script_run_calls(&rp->s, e->start[r], e->start[r + 1], &rp->err);
        s->model->destroy(rp->s.instance);
    }
    for (size_t i = e->start[r]; i < e->start[r + 1]; i++)
        s->calls[i].ctx = &s->ctx; /* (the calls point at the script's context again) */
    if (out)
        fclose(out);
    if (diag)
        fclose(diag);
}

/* The quantities of all replicas, in the order the first replica that gives each gave it. */
typedef struct {
    char (*name)[64];
    size_t n;
    double *mean, *se;
    int *count;
} combined;

static int combine(const replica *rp, int K, combined *cb)
{
    size_t cap = 0;
    for (int r = 0; r < K; r++)
        cap += rp[r].res.n;
    memset(cb, 0, sizeof *cb);
    cb->name = malloc((cap + 1) * sizeof *cb->name);
    cb->mean = malloc((cap + 1) * sizeof *cb->mean);
    cb->se = malloc((cap + 1) * sizeof *cb->se);
    cb->count = malloc((cap + 1) * sizeof *cb->count);
    if (!cb->name || !cb->mean || !cb->se || !cb->count)
        return MOTE_ENOMEM;
    for (int r = 0; r < K; r++)
        for (size_t i = 0; i < rp[r].res.n; i++) {
            size_t q = 0;
            while (q < cb->n && strcmp(cb->name[q], rp[r].res.name[i]) != 0)
                q++;
            if (q == cb->n)
                memcpy(cb->name[cb->n++], rp[r].res.name[i], sizeof cb->name[0]);
        }
    for (size_t q = 0; q < cb->n; q++) { /* two passes, in replica order */
        double sum = 0, ss = 0;
        int n = 0;
        for (int r = 0; r < K; r++)
            for (size_t i = 0; i < rp[r].res.n; i++)
                if (!strcmp(rp[r].res.name[i], cb->name[q])) {
                    sum += rp[r].res.value[i];
                    n++;
                    break;
                }
        const double mean = n ? sum / n : NAN;
        for (int r = 0; r < K; r++)
            for (size_t i = 0; i < rp[r].res.n; i++)
                if (!strcmp(rp[r].res.name[i], cb->name[q])) {
                    ss += (rp[r].res.value[i] - mean) * (rp[r].res.value[i] - mean);
                    break;
                }
        cb->mean[q] = isnan(mean) ? NAN : mean;
        cb->se[q] = n > 1 && !isnan(ss) ? sqrt(ss / (n - 1) / n) : NAN;
        cb->count[q] = n;
    }
    return MOTE_OK;
}

/* The half-width of the 95% confidence interval of quantity q's mean (NaN below 2 values). */
static double ci95(const combined *cb, size_t q)
{
    return cb->count[q] > 1 ? mote_t95(cb->count[q] - 1) * cb->se[q] : NAN;
}

static void combined_free(combined *cb)
{
    free(cb->name);
    free(cb->mean);
    free(cb->se);
    free(cb->count);
}

/* The value of quantity `name` in replica rp, or NaN. */
static double value_of(const replica *rp, const char *name)
{
    for (size_t i = 0; i < rp->res.n; i++)
        if (!strcmp(rp->res.name[i], name))
            return isnan(rp->res.value[i]) ? NAN : rp->res.value[i]; /* ("nan", not "-nan") */
    return NAN;
}

/* file=: every replica's values, with the means and standard errors in the header. */
static int write_file(const mote_script *s, const mote_call *ec, const replica *rp, int K,
                      uint64_t seed, const combined *cb, mote_err *err)
{
    const mote_arg *f = mote_call_opt(ec, "file");
    char *origin = mote_call_origin(ec);
    mote_datafile d;
    int rc = mote_datafile_open(&d, f->path, "ensemble", origin ? origin : "ensemble", seed, err);
    free(origin);
    if (rc)
        return rc;
    fprintf(d.f, "# replicas = %d\n# seed_first = %llu\n", K, (unsigned long long)seed);
    fprintf(d.f, "# errors: standard error of the mean over the replicas, s/sqrt(n); ci95: the "
                 "half-width of its 95%% confidence interval, Student's t(0.975, n - 1) times "
                 "the standard error (n - 1 degrees of freedom)\n");
    for (size_t q = 0; q < cb->n; q++)
        fprintf(d.f, "# %s = %.12g ± %.6g\n# %s_ci95 = %.6g\n", cb->name[q], cb->mean[q],
                cb->se[q], cb->name[q], ci95(cb, q));
    fprintf(d.f, "# columns: replica seed");
    for (size_t q = 0; q < cb->n; q++)
        fprintf(d.f, " %s", cb->name[q]);
    fputc('\n', d.f);
    for (int r = 0; r < K; r++) {
        fprintf(d.f, "%d %llu", r + 1, (unsigned long long)(seed + (uint64_t)r));
        for (size_t q = 0; q < cb->n; q++)
            fprintf(d.f, " %.17g", value_of(&rp[r], cb->name[q]));
        fputc('\n', d.f);
    }
    return mote_datafile_commit(&d, err);
}

/* summary=: one row per ensemble that names the file: the values of the loops around it, then
 * each quantity's mean and standard error; the file is written again, whole, each time. */
static int write_summary(mote_script *s, const mote_call *ec, uint64_t seed, int K,
                         const combined *cb, mote_err *err)
{
    const mote_arg *f = mote_call_opt(ec, "summary");
    mote_ens_summary *sm = NULL;
    for (size_t i = 0; i < s->nsums; i++)
        if (!strcmp(s->sums[i].path, f->path))
            sm = &s->sums[i];
    if (!sm) {
        mote_ens_summary *ns = realloc(s->sums, (s->nsums + 1) * sizeof *ns);
        if (!ns)
            return mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
        s->sums = ns;
        sm = &s->sums[s->nsums++];
        memset(sm, 0, sizeof *sm);
        sm->path = strdup(f->path);
        char *origin = mote_call_origin(ec);
        mote_buf_printf(&sm->head, "# replicas = %d\n# seed_first = %llu\n"
                        "# errors: NAME_err the standard error of the mean over the replicas, "
                        "s/sqrt(n); NAME_ci95 the half-width of its 95%% confidence interval, "
                        "Student's t(0.975, n - 1) times the standard error\n"
                        "# columns:", K, (unsigned long long)seed);
        sm->origin = origin;
        /* the loops' names, then each quantity and its error */
        const char *lp = ec->loop ? ec->loop : "";
        while (*lp) {
            size_t n = strcspn(lp, "=");
            mote_buf_printf(&sm->head, " %.*s", (int)n, lp);
            lp += n;
            lp += strcspn(lp, ",");
            lp += strspn(lp, ", ");
        }
        sm->ncols = (int)cb->n;
        sm->cols = malloc((cb->n + 1) * sizeof *sm->cols);
        if (!sm->path || !sm->cols || !origin)
            return mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
        for (size_t q = 0; q < cb->n; q++) {
            memcpy(sm->cols[q], cb->name[q], sizeof sm->cols[0]);
            mote_buf_printf(&sm->head, " %s %s_err %s_ci95", cb->name[q], cb->name[q],
                            cb->name[q]);
        }
        mote_buf_printf(&sm->head, "\n");
    }
    /* the row: the loops' values, then the columns' means and errors (NaN when absent) */
    const char *lp = ec->loop ? ec->loop : "";
    const char *sep = "";
    while (*lp) {
        lp += strcspn(lp, "=") + 1;
        size_t n = strcspn(lp, ",");
        mote_buf_printf(&sm->rows, "%s%.*s", sep, (int)n, lp);
        sep = " ";
        lp += n;
        lp += strspn(lp, ", ");
    }
    for (int k = 0; k < sm->ncols; k++) {
        size_t q = 0;
        while (q < cb->n && strcmp(cb->name[q], sm->cols[k]) != 0)
            q++;
        mote_buf_printf(&sm->rows, "%s%.12g %.6g %.6g", sep, q < cb->n ? cb->mean[q] : NAN,
                        q < cb->n ? cb->se[q] : NAN, q < cb->n ? ci95(cb, q) : NAN);
        sep = " ";
    }
    mote_buf_printf(&sm->rows, "\n");
    if (sm->head.failed || sm->rows.failed)
        return mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
    mote_datafile d;
    int rc = mote_datafile_open(&d, sm->path, "ensemble-summary", sm->origin, seed, err);
    if (rc)
        return rc;
    fwrite(sm->head.s, 1, sm->head.n, d.f);
    fwrite(sm->rows.s, 1, sm->rows.n, d.f);
    return mote_datafile_commit(&d, err);
}

void mote_ensemble_free_summaries(mote_script *s)
{
    for (size_t i = 0; i < s->nsums; i++) {
        free(s->sums[i].path);
        free(s->sums[i].origin);
        free(s->sums[i].cols);
        mote_buf_free(&s->sums[i].head);
        mote_buf_free(&s->sums[i].rows);
    }
    free(s->sums);
    s->sums = NULL;
    s->nsums = 0;
}

/* ---- under mpirun: the replicas' outcomes, from every rank to every rank ---- */

int mote_ranks_sync(mote_script *s, int finished)
{
    const mote_ranks *rk = s->ctx.ranks;
    if (!rk || rk->size < 2 || s->ranks_finished)
        return 0;
    const char mine = (char)finished;
    size_t *lens = calloc((size_t)rk->size, sizeof *lens);
    char *all = lens ? rk->allgather(rk, &mine, 1, lens) : NULL;
    int stopped = !all;
    for (int k = 0; all && k < rk->size; k++)
        stopped |= all[k] != 0;
    free(all);
    free(lens);
    if (stopped) /* (a rank that stopped called this for the last time: no more calls here) */
        s->ranks_finished = 1;
    return stopped;
}

static void put(mote_buf *b, const void *p, size_t n) { mote_buf_append(b, p, n); }

/* Record of one replica: r, rc, the error, its output, its warnings, its results. */
static void put_replica(mote_buf *b, int r, const replica *rp)
{
    const uint64_t h[6] = {(uint64_t)r, (uint64_t)(int64_t)rp->rc, (uint64_t)rp->err.code,
                           (uint64_t)rp->err.located, rp->out ? rp->nout : 0,
                           rp->diag ? rp->ndiag : 0};
    put(b, h, sizeof h);
    put(b, rp->err.msg, sizeof rp->err.msg);
    put(b, rp->out, h[4]);
    put(b, rp->diag, h[5]);
    const uint64_t nres = rp->res.failed ? UINT64_MAX : rp->res.n;
    put(b, &nres, sizeof nres);
    for (size_t i = 0; nres != UINT64_MAX && i < rp->res.n; i++) {
        put(b, rp->res.name[i], sizeof rp->res.name[0]);
        put(b, &rp->res.value[i], sizeof(double));
    }
}

/* Read the records in [p, end) into rp (those of other ranks). Returns -1 when malformed or
 * out of memory. */
static int get_replicas(const char *p, const char *end, replica *rp, int K)
{
    while (p < end) {
        uint64_t h[6], nres;
        if ((size_t)(end - p) < sizeof h)
            return -1;
        memcpy(h, p, sizeof h);
        p += sizeof h;
        const int r = (int)h[0];
        if (r < 0 || r >= K || (size_t)(end - p) < sizeof rp->err.msg + h[4] + h[5] + sizeof nres)
            return -1;
        replica *q = &rp[r];
        q->rc = (int)(int64_t)h[1];
        q->err.code = (mote_status)h[2];
        q->err.located = (int)h[3];
        memcpy(q->err.msg, p, sizeof q->err.msg);
        p += sizeof q->err.msg;
        q->out = malloc(h[4] + 1);
        q->diag = malloc(h[5] + 1);
        if (!q->out || !q->diag)
            return -1;
        memcpy(q->out, p, h[4]);
        q->nout = h[4];
        p += h[4];
        memcpy(q->diag, p, h[5]);
        q->ndiag = h[5];
        p += h[5];
        memcpy(&nres, p, sizeof nres);
        p += sizeof nres;
        if (nres == UINT64_MAX) {
            q->res.failed = 1;
            continue;
        }
        if ((size_t)(end - p) / (64 + sizeof(double)) < nres)
            return -1;
        for (uint64_t i = 0; i < nres; i++) {
            char name[64];
            double v;
            memcpy(name, p, sizeof name);
            memcpy(&v, p + 64, sizeof v);
            p += 64 + sizeof v;
            name[63] = '\0';
            if (q->res.n == q->res.cap) {
                size_t cap = q->res.cap ? 2 * q->res.cap : 16;
                char(*nn)[64] = realloc(q->res.name, cap * sizeof *nn);
                if (nn)
                    q->res.name = nn;
                double *nv = nn ? realloc(q->res.value, cap * sizeof *nv) : NULL;
                if (!nn || !nv)
                    return -1;
                q->res.value = nv;
                q->res.cap = cap;
            }
            memcpy(q->res.name[q->res.n], name, sizeof name);
            q->res.value[q->res.n++] = v;
        }
    }
    return 0;
}

/* Every rank sends its replicas' records and reads the others'. */
static int exchange(const mote_ranks *rk, replica *rp, int K)
{
    mote_buf b = {0};
    for (int r = rk->rank; r < K; r += rk->size)
        put_replica(&b, r, &rp[r]);
    size_t *lens = calloc((size_t)rk->size, sizeof *lens);
    char *all = lens ? rk->allgather(rk, b.failed ? NULL : b.s, b.failed ? 0 : b.n, lens) : NULL;
    int rc = all && !b.failed ? 0 : -1;
    size_t at = 0;
    for (int k = 0; k < rk->size && !rc; k++) {
        if (k != rk->rank)
            rc = get_replicas(all + at, all + at + lens[k], rp, K);
        at += lens[k];
    }
    free(all);
    free(lens);
    free(b.s);
    return rc;
}

/* The pool: each worker takes the next replica not yet taken, until none is left. */
typedef struct {
    mote_script *s;
    const mote_ensemble *e;
    replica *rp;
    pthread_mutex_t lock;
    int next, stride, done, mine; /* under mpirun: this rank's replicas, every stride-th */
    int solo;
    mote_progress *prog;
    ens_stop *st;
    int active;           /* workers not yet done */
    pthread_cond_t idle;  /* signalled as each is done */
} pool;

static void *worker(void *arg)
{
    pool *p = arg;
    for (;;) {
        pthread_mutex_lock(&p->lock);
        const int r = p->next < p->e->K && !atomic_load(&p->st->stop) ? p->next : -1;
        p->next += p->stride;
        pthread_mutex_unlock(&p->lock);
        if (r < 0) {
            pthread_mutex_lock(&p->lock);
            p->active--;
            pthread_cond_signal(&p->idle);
            pthread_mutex_unlock(&p->lock);
            return NULL;
        }
        run_replica(p->s, p->e, r, &p->rp[r], p->solo, p->st);
        pthread_mutex_lock(&p->lock);
        p->done++;
        if (mote_progress_update(p->prog, (double)p->done / p->mine))
            atomic_store(&p->st->stop, 1);
        pthread_mutex_unlock(&p->lock);
    }
}

int mote_ensemble_run(mote_script *s, const mote_ensemble *e, mote_err *err)
{
    const mote_call *ec = &s->calls[e->call];
    const int K = e->K;
    const mote_arg *sa = mote_call_opt(ec, "seed");
    const uint64_t seed = sa ? sa->u : 1;
    replica *rp = calloc((size_t)K, sizeof *rp);
    if (!rp)
        return mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
    /* under mpirun, rank k runs the replicas k, k + size, ... (each in that rank alone), and the
     * ranks then exchange what their replicas printed and measured */
    const mote_ranks *rk = s->ctx.ranks && s->ctx.ranks->size > 1 ? s->ctx.ranks : NULL;
    const int first = rk ? rk->rank : 0, stride = rk ? rk->size : 1;
    const int mine = first < K ? (K - first + stride - 1) / stride : 0;
    /* every rank here (so what rank 0 wrote before is there for the replicas), unless a rank
     * has stopped: then this rank stops too */
    if (rk && mote_ranks_sync(s, 0)) {
        free(rp);
        return mote_call_fail(err, ec, -1, MOTE_ERUNTIME, "ensemble: another MPI rank stopped "
                              "before it (its error is on rank 0's output)");
    }
    long procs = sysconf(_SC_NPROCESSORS_ONLN);
    int threads = s->ctx.threads > 0 ? s->ctx.threads : procs > 0 ? (int)procs : 1;
    if (threads > (mine > 0 ? mine : 1))
        threads = mine > 0 ? mine : 1;
    fprintf(s->ctx.out, "ensemble: %d replica%s (seeds %llu ... %llu) on %d thread%s", K,
            K == 1 ? "" : "s", (unsigned long long)seed,
            (unsigned long long)(seed + (uint64_t)K - 1), threads, threads == 1 ? "" : "s");
    if (rk)
        fprintf(s->ctx.out, " in each of %d MPI ranks", rk->size);
    fputc('\n', s->ctx.out);
    fflush(s->ctx.out);
    mote_progress prog;
    mote_progress_begin(&prog, &s->ctx, "ensemble");
    ens_stop st = {0, pthread_self(), s->ctx.interrupt, s->ctx.interrupt_arg};
    pool p = {s, e, rp, PTHREAD_MUTEX_INITIALIZER, first, stride, 0, mine, rk != NULL, &prog, &st,
              0, PTHREAD_COND_INITIALIZER};
    pthread_t *tid = malloc((size_t)threads * sizeof *tid);
    int started = 0;
    p.active = tid ? threads : 1; /* (set before any worker runs: each counts itself out) */
    for (int k = 1; tid && k < threads; k++) /* (this thread is the first worker) */
        started += pthread_create(&tid[started], NULL, worker, &p) == 0;
    pthread_mutex_lock(&p.lock);
    p.active -= (tid ? threads - 1 : 0) - started; /* (those that did not start) */
    pthread_mutex_unlock(&p.lock);
    worker(&p);
    /* this thread's replicas done: it asks the interrupt hook while the others finish theirs */
    pthread_mutex_lock(&p.lock);
    while (p.active > 0) {
        const struct timespec until = mote_deadline(0.05);
        pthread_cond_timedwait(&p.idle, &p.lock, &until);
        if (p.active > 0 && st.hook && !atomic_load(&st.stop)) {
            pthread_mutex_unlock(&p.lock);
            if (st.hook(st.arg))
                atomic_store(&st.stop, 1);
            pthread_mutex_lock(&p.lock);
        }
    }
    pthread_mutex_unlock(&p.lock);
    for (int k = 0; k < started; k++)
        pthread_join(tid[k], NULL);
    pthread_cond_destroy(&p.idle);
    free(tid);
    mote_progress_end(&prog);
    int rc = 0;
    if (atomic_load(&st.stop)) /* (the hook is Python's: one process, no MPI partner) */
        rc = mote_interrupted(err, "ensemble");
    else if (rk && exchange(rk, rp, K))
        rc = mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory exchanging the "
                            "replicas among the MPI ranks");
    for (int r = 0; r < K && !rc; r++) { /* what each printed, in replica order */
        fprintf(s->ctx.out, "ensemble: replica %d (seed %llu)\n", r + 1,
                (unsigned long long)(seed + (uint64_t)r));
        if (rp[r].out)
            fwrite(rp[r].out, 1, rp[r].nout, s->ctx.out);
        if (rp[r].diag)
            fwrite(rp[r].diag, 1, rp[r].ndiag, s->ctx.diag);
    }
    for (int r = 0; r < K && !rc; r++) /* the earliest replica that failed */
        if (rp[r].rc || rp[r].res.failed) {
            rc = rp[r].rc ? rp[r].rc : MOTE_ENOMEM;
            *err = rp[r].err;
            if (!rp[r].rc)
                mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
        }
    combined cb = {0};
    if (!rc && combine(rp, K, &cb))
        rc = mote_call_fail(err, ec, -1, MOTE_ENOMEM, "ensemble: out of memory");
    else if (!rc) {
        for (size_t q = 0; q < cb.n; q++) {
            if (cb.count[q] < 2) {
                fprintf(s->ctx.out, "ensemble: %s = %.10g (%d replica: no error estimate)\n",
                        cb.name[q], cb.mean[q], cb.count[q]);
                continue;
            }
            fprintf(s->ctx.out, "ensemble: %s = %.10g ± %.4g (95%% confidence; standard error "
                    "%.4g, Student's t %.4g with %d degree%s of freedom; %d replicas)\n",
                    cb.name[q], cb.mean[q], ci95(&cb, q), cb.se[q], mote_t95(cb.count[q] - 1),
                    cb.count[q] - 1, cb.count[q] == 2 ? "" : "s", cb.count[q]);
        }
        if (K < 4 && cb.n && !s->ens_warned++)
            fprintf(s->ctx.diag, "ensemble: warning: %d replica%s: the spread of so few values "
                    "says little about the error (the 95%% interval is %.3g standard errors "
                    "wide each way); 4 or more give a useful estimate\n", K, K == 1 ? "" : "s",
                    K > 1 ? mote_t95(K - 1) : INFINITY);
        if (!cb.n)
            fprintf(s->ctx.out, "ensemble: no command in it measured anything to average\n");
        const int writer = !rk || rk->rank == 0; /* (under mpirun rank 0 writes) */
        if (writer && mote_call_opt(ec, "file"))
            rc = write_file(s, ec, rp, K, seed, &cb, err);
        if (!rc && writer && mote_call_opt(ec, "summary"))
            rc = write_summary(s, ec, seed, K, &cb, err);
    }
    combined_free(&cb);
    for (int r = 0; r < K; r++) {
        free(rp[r].out);
        free(rp[r].diag);
        mote_results_free(&rp[r].res);
    }
    free(rp);
    return rc;
}
