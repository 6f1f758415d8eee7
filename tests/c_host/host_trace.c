/*
 * host_trace.c -- the trace commands of the C FMI hosts (host_internal.h): `trace` (Co-Simulation)
 * and `trace_me` (Model Exchange, the call sequence of wearjoint's core/joint_access.py at an
 * accepted point, with the event iteration), over the rows of a table file.
 */
#define _GNU_SOURCE
#include "host_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_EVENT_ITERATIONS 1000

/* Read rows of ncol doubles ('#' comments and blank lines skipped) into a scratch buffer. */
static double *read_table(const char *cmd, const char *path, size_t ncol, size_t *rows_out)
{
    size_t slot = HOST_N_SCRATCH, rows = 0, cap = 0;
    double *data = NULL;
    char *buf = NULL;
    size_t bufcap = 0;
    long file_line = 0;
    FILE *f;
    for (size_t i = 0; i < HOST_N_SCRATCH; i++)
        if (host_scratch_buffers[i] == NULL) {
            slot = i;
            break;
        }
    if (slot == HOST_N_SCRATCH)
        host_die2("internal error: scratch buffers exhausted");
    f = fopen(path, "r");
    if (f == NULL)
        host_die2("%s: cannot open '%s': %s", cmd, path, strerror(errno));
    while (host_read_line(&buf, &bufcap, f) != -1) {
        char *p = buf, *end;
        size_t k = 0;
        file_line++;
        while (*p == ' ' || *p == '\t')
            p++;
        if (*p == '#' || *p == '\n' || *p == '\r' || *p == '\0')
            continue;
        if (rows + 1 > cap) {
            size_t ncap = cap ? 2 * cap : 1024;
            double *d = realloc(data, ncap * ncol * sizeof *d);
            if (d == NULL) {
                free(buf);
                fclose(f);
                host_die2("out of memory reading '%s'", path);
            }
            data = d;
            host_scratch_buffers[slot] = d; /* every exit frees it */
            cap = ncap;
        }
        for (;;) {
            double v;
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
                p++;
            if (*p == '\0')
                break;
            errno = 0;
            v = strtod(p, &end);
            if (end == p || errno == ERANGE || k >= ncol ||
                !(*end == '\0' || *end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')) {
                free(buf);
                fclose(f);
                host_die2("%s: %s line %ld: expected %zu numbers (t h u1..u%zu)", cmd, path, file_line, ncol,
                          ncol - 2);
            }
            data[rows * ncol + k++] = v;
            p = end;
        }
        if (k != ncol) {
            free(buf);
            fclose(f);
            host_die2("%s: %s line %ld: expected %zu numbers (t h u1..u%zu), got %zu", cmd, path, file_line, ncol,
                      ncol - 2, k);
        }
        rows++;
    }
    free(buf);
    fclose(f);
    *rows_out = rows;
    return data;
}

enum { EVENT_NONE, EVENT_ONSET, EVENT_SEPARATION, EVENT_REQUESTED };
static const char *const EVENT_NAMES[] = {"", "onset", "separation", "requested"};

typedef struct {
    size_t n_in, n_out, ncol, rows;
    unsigned *in_vr, *out_vr;
    double *data, *out;
    unsigned char *event;        /* trace_me: per row, EVENT_* */
    int events_first;            /* trace_me: the event iteration before fmi*CompletedIntegratorStep */
    /* the run */
    size_t done, fail_row;       /* rows whose outputs are valid; the row of a failure */
    int status, worst, failed;   /* the last status, the worst one, the failing call (-1: none) */
    int stuck, terminated;
    size_t events[4];
} Trace;

/* 1 if the call succeeded (ok/warning); else the failure is recorded */
static int call_ok(Trace *t, int status, int call)
{
    t->status = status;
    if (status > t->worst)
        t->worst = status;
    if (status == HOST_OK || status == HOST_WARNING)
        return 1;
    t->failed = call;
    return 0;
}

/* enter event mode, update the discrete states until none is needed, back to continuous time */
static int event_iteration(Trace *t)
{
    const HostOps *ops = H.ops;
    if (!call_ok(t, ops->call(H.instance, CALL_ENTER_EVENT_MODE), CALL_ENTER_EVENT_MODE))
        return 0;
    for (int k = 0;; k++) {
        HostEventInfo info;
        memset(&info, 0, sizeof info);
        if (!call_ok(t, ops->new_discrete_states(&info), CALL_NEW_DISCRETE_STATES))
            return 0;
        if (info.terminate) {
            t->terminated = 1;
            return 0;
        }
        if (!info.needed)
            break;
        if (k + 1 >= MAX_EVENT_ITERATIONS) {
            t->stuck = 1;
            t->status = HOST_ERROR;
            t->failed = CALL_NEW_DISCRETE_STATES;
            return 0;
        }
    }
    return call_ok(t, ops->call(H.instance, CALL_ENTER_CONTINUOUS_TIME_MODE), CALL_ENTER_CONTINUOUS_TIME_MODE);
}

/* set the inputs and read the outputs of row i; 1 on success */
static int inputs_outputs(Trace *t, size_t i)
{
    const double *row = t->data + i * t->ncol;
    if (t->n_in > 0 && !call_ok(t, H.ops->set_reals(t->in_vr, t->n_in, row + 2), CALL_SET_REALS))
        return 0;
    if (t->n_out > 0 && !call_ok(t, H.ops->get_reals(t->out_vr, t->n_out, t->out + i * t->n_out), CALL_GET_REALS))
        return 0;
    t->done = i + 1; /* outputs of row i are valid */
    return 1;
}

static int cs_row(Trace *t, size_t i)
{
    const double *row = t->data + i * t->ncol;
    return inputs_outputs(t, i) && call_ok(t, H.ops->do_step(row[0], row[1], 1, NULL, 0), CALL_DO_STEP);
}

/* Model Exchange: what wearjoint/core/joint_access.py does at an accepted point */
static int me_row(Trace *t, size_t i)
{
    const HostOps *ops = H.ops;
    double z = 0.0;
    int enter = 0, terminate = 0, contact, event;
    if (!call_ok(t, ops->set_time(t->data[i * t->ncol]), CALL_SET_TIME) || !inputs_outputs(t, i) ||
        !call_ok(t, ops->get_vector(CALL_GET_EVENT_INDICATORS, &z, 1), CALL_GET_EVENT_INDICATORS))
        return 0;
    contact = z >= 0.0;
    event = contact != H.me_contact;
    if (event && t->events_first && !event_iteration(t))
        return 0;
    if (!call_ok(t, ops->completed_integrator_step(1, &enter, &terminate), CALL_COMPLETED_INTEGRATOR_STEP))
        return 0;
    if (terminate) {
        t->terminated = 1;
        return 0;
    }
    if (((event && !t->events_first) || enter) && !event_iteration(t))
        return 0;
    if (event || enter) {
        t->event[i] = event ? (contact ? EVENT_ONSET : EVENT_SEPARATION) : EVENT_REQUESTED;
        t->events[t->event[i]]++;
        H.me_contact = contact;
    }
    return 1;
}

/* trace <file> <n_inputs> <in_vrs> <out_vrs>  |  trace_me ... [events_after|events_first] */
void host_trace(size_t ntok, int me)
{
    const char *cmd = H.tok[0];
    char what[64];
    Trace t;
    size_t n_in_list;
    double t0;
    memset(&t, 0, sizeof t);
    t.failed = -1;
    snprintf(what, sizeof what, "%s n_inputs", cmd);
    t.n_in = (size_t)host_parse_long(H.tok[2], 0, 1000000, what);
    n_in_list = host_parse_vr_list(H.tok[3], &t.in_vr);
    t.n_out = host_parse_vr_list(H.tok[4], &t.out_vr);
    if (ntok > 5 && strcmp(H.tok[5], "events_first") != 0 && strcmp(H.tok[5], "events_after") != 0)
        host_die2("%s: the event order is events_after or events_first, got '%s'", cmd, H.tok[5]);
    t.events_first = ntok > 5 && strcmp(H.tok[5], "events_first") == 0;
    host_need_instance();
    if (n_in_list != t.n_in)
        host_die2("%s: n_inputs is %zu but %zu input value references were given", cmd, t.n_in, n_in_list);
    if (t.n_in > 0)
        host_fn(CALL_SET_REALS);
    if (t.n_out > 0)
        host_fn(CALL_GET_REALS);
    if (me) {
        static const int calls[] = {CALL_SET_TIME, CALL_GET_EVENT_INDICATORS, CALL_COMPLETED_INTEGRATOR_STEP,
                                    CALL_ENTER_EVENT_MODE, CALL_NEW_DISCRETE_STATES, CALL_ENTER_CONTINUOUS_TIME_MODE};
        for (size_t k = 0; k < sizeof calls / sizeof calls[0]; k++)
            host_fn(calls[k]);
    } else {
        host_fn(CALL_DO_STEP);
    }
    t.ncol = 2 + t.n_in;
    t.data = read_table(cmd, H.tok[1], t.ncol, &t.rows);
    t.out = host_scratch(t.rows * t.n_out * sizeof *t.out);
    t.event = host_scratch(t.rows);

    t0 = host_now();
    for (size_t i = 0; i < t.rows; i++) {
        if (!(me ? me_row(&t, i) : cs_row(&t, i))) {
            t.fail_row = i;
            break;
        }
    }
    fprintf(stderr, "trace_seconds %.6f\n", host_now() - t0);

    for (size_t i = 0; i < t.done; i++) {
        printf("out %.17g", t.data[i * t.ncol]);
        for (size_t j = 0; j < t.n_out; j++)
            printf(" %.17g", t.out[i * t.n_out + j]);
        printf("\n");
        if (t.event[i] != EVENT_NONE)
            printf("event %.17g %s\n", t.data[i * t.ncol], EVENT_NAMES[t.event[i]]);
    }
    if (t.stuck)
        fprintf(stderr, "%s: %s: %s still needs new discrete states after %d iterations\n", H.ops->host, cmd,
                H.ops->names[CALL_NEW_DISCRETE_STATES], MAX_EVENT_ITERATIONS);
    if (t.failed >= 0) {
        host_check(t.status, H.ops->names[t.failed]);
        printf("%s %s row=%zu call=%s", cmd, host_status_name(t.status), t.fail_row, H.ops->names[t.failed]);
    } else {
        host_check(t.worst, cmd);
        printf("%s %s rows=%zu", cmd, host_status_name(t.worst), t.terminated ? t.fail_row + 1 : t.rows);
    }
    if (me)
        printf(" events=%zu onsets=%zu separations=%zu%s", t.events[EVENT_ONSET] + t.events[EVENT_SEPARATION] +
               t.events[EVENT_REQUESTED], t.events[EVENT_ONSET], t.events[EVENT_SEPARATION],
               t.terminated ? " terminate=1" : "");
    printf("\n");
}
