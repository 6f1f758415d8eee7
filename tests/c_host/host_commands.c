/*
 * host_commands.c -- the commands both C FMI hosts share, but the traces (host_trace.c): instances
 * (instantiate, free, cycle, time_load), FMU states, the Model Exchange calls one at a time, the
 * directional derivative, and their dispatch (documented at the top of host_common.h).
 */
#define _GNU_SOURCE
#include "host_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------- */
/* Instances                                                                 */

static int instantiate_call(int model_exchange)
{
    return model_exchange ? CALL_INSTANTIATE_ME : CALL_INSTANTIATE_CS;
}

/* the calls of instantiate .. initialized .. free exist (checked before an instance is made) */
static void require_lifecycle(int model_exchange)
{
    static const int calls[] = {CALL_SETUP_EXPERIMENT, CALL_ENTER_INIT, CALL_EXIT_INIT, CALL_FREE_INSTANCE};
    host_fn(instantiate_call(model_exchange));
    for (size_t i = 0; i < sizeof calls / sizeof calls[0]; i++)
        if (H.ops->names[calls[i]] != NULL)
            host_fn(calls[i]);
}

/* setup (FMI 2.0) + enter + exit initialization with default arguments; the status of the last
 * call made, *failed the failing call or -1 */
static int initialize(void *instance, int *failed)
{
    static const int calls[] = {CALL_SETUP_EXPERIMENT, CALL_ENTER_INIT, CALL_EXIT_INIT};
    int s = HOST_OK;
    *failed = -1;
    for (size_t i = 0; i < sizeof calls / sizeof calls[0]; i++) {
        if (H.ops->names[calls[i]] == NULL)
            continue;
        s = H.ops->call(instance, calls[i]);
        if (s > HOST_WARNING) {
            *failed = calls[i];
            break;
        }
    }
    return s;
}

static void cmd_instantiate(size_t ntok, int model_exchange)
{
    const char *cmd = H.tok[0];
    int call = instantiate_call(model_exchange);
    host_need_args(ntok, 1, 2, model_exchange ? "instantiate_me <name> [<token>]" : "instantiate <name> [<token>]");
    if (H.instance != NULL)
        host_die2("%s: an instance exists already; 'free' it first", cmd);
    host_fn(call);
    H.instance = H.ops->instantiate(H.tok[1], ntok > 2 ? H.tok[2] : H.token, model_exchange);
    H.me_contact = 0;
    host_check(H.instance != NULL ? HOST_OK : HOST_ERROR, H.ops->names[call]);
    printf("%s %s\n", cmd, H.instance != NULL ? "ok" : "null");
}

static void cmd_free(void)
{
    const char *free_state = H.ops->names[CALL_FREE_STATE];
    host_need_instance();
    for (int i = 0; i < NSLOTS; i++) {
        if (H.slots[i] != NULL) {
            host_fn(CALL_FREE_STATE);
            fprintf(stderr, "%s: note: freeing the FMU state in slot %d before %s\n", H.ops->host, i,
                    H.ops->names[CALL_FREE_INSTANCE]);
            if (host_check(H.ops->free_state(&H.slots[i]), free_state) > HOST_WARNING)
                host_die1("%s(slot %d) returned %s", free_state, i, host_status_name(H.last_status));
            H.slots[i] = NULL;
        }
    }
    host_fn(CALL_FREE_INSTANCE);
    H.ops->free_instance(H.instance);
    H.instance = NULL;
    H.last_status = HOST_OK;
    printf("free ok\n");
}

static void cmd_cycle(long n, const char *name)
{
    long before = host_rss_kb(), after, k = 0;
    int s = HOST_OK, failed = -1;
    require_lifecycle(H.model_exchange);
    for (; k < n; k++) {
        void *c = H.ops->instantiate(name, H.token, H.model_exchange);
        if (c == NULL) {
            s = HOST_ERROR;
            failed = instantiate_call(H.model_exchange);
            break;
        }
        s = initialize(c, &failed);
        if (s == HOST_FATAL)
            break; /* the instance must not be touched again */
        H.ops->free_instance(c);
        if (failed >= 0)
            break;
    }
    after = host_rss_kb();
    fprintf(stderr, "rss_kb_before %ld\nrss_kb_after %ld\n", before, after);
    if (failed >= 0) {
        host_check(s, H.ops->names[failed]);
        printf("cycle %s iterations=%ld call=%s\n", host_status_name(s), k, H.ops->names[failed]);
    } else {
        host_check(HOST_OK, "cycle");
        printf("cycle ok iterations=%ld\n", k);
    }
}

static void cmd_time_load(const char *name)
{
    int s, failed = -1, call = instantiate_call(H.model_exchange);
    double t_end;
    if (H.instance != NULL)
        host_die2("time_load: an instance exists already; make time_load the first command");
    require_lifecycle(H.model_exchange);
    H.instance = H.ops->instantiate(name, H.token, H.model_exchange);
    H.me_contact = 0;
    if (H.instance == NULL) {
        host_check(HOST_ERROR, H.ops->names[call]);
        printf("time_load error call=%s\n", H.ops->names[call]);
        return;
    }
    s = initialize(H.instance, &failed);
    t_end = host_now();
    if (failed < 0) {
        fprintf(stderr, "startup_seconds %.6f\n", t_end - H.t_main);
        fprintf(stderr, "startup_seconds_since_exec %.3f\n", host_seconds_since_exec());
        printf("time_load %s\n", host_status_name(s));
    } else {
        host_check(s, H.ops->names[failed]);
        printf("time_load %s call=%s\n", host_status_name(s), H.ops->names[failed]);
    }
}

/* ------------------------------------------------------------------------- */
/* FMU states                                                                */

static void cmd_state(const char *cmd, int slot)
{
    int s;
    host_need_instance();
    if (strcmp(cmd, "get_state") == 0) {
        host_fn(CALL_GET_STATE);
        s = host_check(H.ops->get_state(&H.slots[slot]), H.ops->names[CALL_GET_STATE]);
        H.slot_contact[slot] = H.me_contact;
        printf("get_state %d %s\n", slot, host_status_name(s));
    } else if (strcmp(cmd, "set_state") == 0) {
        host_fn(CALL_SET_STATE);
        s = host_check(H.ops->set_state(H.slots[slot]), H.ops->names[CALL_SET_STATE]);
        if (s <= HOST_WARNING)
            H.me_contact = H.slot_contact[slot];
        printf("set_state %d %s\n", slot, host_status_name(s));
    } else {
        host_fn(CALL_FREE_STATE);
        s = host_check(H.ops->free_state(&H.slots[slot]), H.ops->names[CALL_FREE_STATE]);
        printf("free_state %d %s pointer_null=%d\n", slot, host_status_name(s), H.slots[slot] == NULL);
    }
}

static void cmd_serialize(int slot, const char *path)
{
    size_t size = 0;
    void *bytes;
    FILE *f;
    int s;
    host_need_instance();
    host_fn(CALL_SERIALIZED_SIZE);
    host_fn(CALL_SERIALIZE);
    s = host_check(H.ops->serialized_size(H.slots[slot], &size), H.ops->names[CALL_SERIALIZED_SIZE]);
    if (s > HOST_WARNING) {
        printf("serialize %d %s bytes=0\n", slot, host_status_name(s));
        return;
    }
    bytes = host_scratch(size);
    s = host_check(H.ops->serialize(H.slots[slot], bytes, size), H.ops->names[CALL_SERIALIZE]);
    printf("serialize %d %s bytes=%zu\n", slot, host_status_name(s), size);
    if (s > HOST_WARNING)
        return;
    f = fopen(path, "wb");
    if (f == NULL)
        host_die2("serialize: cannot create '%s': %s", path, strerror(errno));
    if (fwrite(bytes, 1, size, f) != size) {
        fclose(f);
        host_die2("serialize: cannot write '%s'", path);
    }
    if (fclose(f) != 0)
        host_die2("serialize: cannot write '%s': %s", path, strerror(errno));
}

static void cmd_deserialize(int slot, const char *path)
{
    long len;
    size_t size;
    void *bytes;
    int s;
    FILE *f;
    host_need_instance();
    host_fn(CALL_DESERIALIZE);
    f = fopen(path, "rb");
    if (f == NULL)
        host_die2("deserialize: cannot open '%s': %s", path, strerror(errno));
    if (fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        host_die2("deserialize: cannot read '%s'", path);
    }
    size = (size_t)len;
    bytes = host_scratch(size);
    if (fread(bytes, 1, size, f) != size) {
        fclose(f);
        host_die2("deserialize: cannot read '%s'", path);
    }
    fclose(f);
    if (H.slots[slot] != NULL) {
        host_fn(CALL_FREE_STATE);
        s = host_check(H.ops->free_state(&H.slots[slot]), H.ops->names[CALL_FREE_STATE]);
        if (s > HOST_WARNING) {
            printf("deserialize %d %s bytes=%zu\n", slot, host_status_name(s), size);
            return;
        }
        H.slots[slot] = NULL;
    }
    s = host_check(H.ops->deserialize(bytes, size, &H.slots[slot]), H.ops->names[CALL_DESERIALIZE]);
    H.slot_contact[slot] = 0;
    printf("deserialize %d %s bytes=%zu\n", slot, host_status_name(s), size);
}

/* ------------------------------------------------------------------------- */
/* Model Exchange calls one at a time                                        */

/* get_event_indicators <ni>, get_continuous_states <nx>, get_derivatives <nx> */
static void cmd_get_vector(int call, const char *label, const char *count)
{
    const char *cmd = H.tok[0];
    size_t n = (size_t)host_parse_long(count, 0, 1000000, cmd);
    double *v = host_scratch(n * sizeof *v);
    int s;
    host_need_instance();
    host_fn(call);
    s = host_check(H.ops->get_vector(call, v, n), H.ops->names[call]);
    printf("%s %s\n", cmd, host_status_name(s));
    if (s <= HOST_WARNING)
        for (size_t i = 0; i < n; i++)
            printf("%s %zu %.17g\n", label, i, v[i]);
}

static void cmd_new_discrete_states(void)
{
    HostEventInfo info;
    int s;
    memset(&info, 0, sizeof info);
    host_need_instance();
    host_fn(CALL_NEW_DISCRETE_STATES);
    s = host_check(H.ops->new_discrete_states(&info), H.ops->names[CALL_NEW_DISCRETE_STATES]);
    printf("%s %s", H.tok[0], host_status_name(s));
    if (s <= HOST_WARNING)
        printf(" needed=%d terminate=%d nominals_changed=%d values_changed=%d next_event_time_defined=%d "
               "next_event_time=%.17g", info.needed, info.terminate, info.nominals_changed, info.values_changed,
               info.next_time_defined, info.next_time);
    printf("\n");
}

static void cmd_completed_integrator_step(size_t ntok)
{
    int enter = 0, terminate = 0, s;
    int no_set = ntok > 1 ? host_parse_bool(H.tok[1]) : 1;
    host_need_instance();
    host_fn(CALL_COMPLETED_INTEGRATOR_STEP);
    s = host_check(H.ops->completed_integrator_step(no_set, &enter, &terminate),
                   H.ops->names[CALL_COMPLETED_INTEGRATOR_STEP]);
    printf("completed_integrator_step %s", host_status_name(s));
    if (s <= HOST_WARNING)
        printf(" enter_event_mode=%d terminate=%d", enter, terminate);
    printf("\n");
}

/* directional_derivative <unknown_vrs> <known_vrs> <seed,..> */
static void cmd_directional_derivative(void)
{
    unsigned *unknowns, *knowns;
    size_t n_unknowns = host_parse_vr_list(H.tok[1], &unknowns), n_knowns = host_parse_vr_list(H.tok[2], &knowns),
           k = 0;
    double *seed = host_scratch((n_knowns + 1) * sizeof *seed);
    double *sensitivity = host_scratch((n_unknowns + 1) * sizeof *sensitivity);
    char *cursor = strcmp(H.tok[3], "-") == 0 ? "" : H.tok[3];
    int s;
    for (char *p = host_next_token(&cursor, ","); p != NULL; p = host_next_token(&cursor, ",")) {
        if (k == n_knowns)
            host_die2("directional_derivative: more seed values than the %zu knowns", n_knowns);
        seed[k++] = host_parse_double(p, "seed");
    }
    if (k != n_knowns)
        host_die2("directional_derivative: %zu seed values for %zu knowns", k, n_knowns);
    host_need_instance();
    host_fn(CALL_GET_DIRECTIONAL_DERIVATIVE);
    s = host_check(H.ops->directional_derivative(unknowns, n_unknowns, knowns, n_knowns, seed, sensitivity),
                   H.ops->names[CALL_GET_DIRECTIONAL_DERIVATIVE]);
    printf("directional_derivative %s\n", host_status_name(s));
    if (s <= HOST_WARNING)
        for (size_t i = 0; i < n_unknowns; i++)
            printf("sensitivity %u %.17g\n", unknowns[i], sensitivity[i]);
}

/* ------------------------------------------------------------------------- */
/* Dispatch                                                                  */

/* commands that call one function of the instance alone: "<command> <status>" */
static const struct {
    const char *command;
    int call;
} INSTANCE_CALLS[] = {
    {"enter_init", CALL_ENTER_INIT}, {"exit_init", CALL_EXIT_INIT}, {"terminate", CALL_TERMINATE},
    {"reset", CALL_RESET}, {"enter_config", CALL_ENTER_CONFIG}, {"exit_config", CALL_EXIT_CONFIG},
    {"enter_event_mode", CALL_ENTER_EVENT_MODE}, {"enter_continuous_time_mode", CALL_ENTER_CONTINUOUS_TIME_MODE},
};

int host_execute_common(size_t ntok)
{
    const char *cmd = H.tok[0];
    const HostOps *ops = H.ops;
    int s;

    for (size_t i = 0; i < sizeof INSTANCE_CALLS / sizeof INSTANCE_CALLS[0]; i++) {
        int call = INSTANCE_CALLS[i].call;
        if (strcmp(cmd, INSTANCE_CALLS[i].command) != 0 || ops->names[call] == NULL)
            continue;
        host_need_args(ntok, 0, 0, cmd);
        host_need_instance();
        host_fn(call);
        s = host_check(ops->call(H.instance, call), ops->names[call]);
        if (call == CALL_RESET)
            H.me_contact = 0;
        printf("%s %s\n", cmd, host_status_name(s));
        return 1;
    }
    if (strcmp(cmd, "instantiate") == 0 || strcmp(cmd, "instantiate_me") == 0) {
        cmd_instantiate(ntok, strcmp(cmd, "instantiate_me") == 0 || H.model_exchange);
    } else if (strcmp(cmd, "free") == 0) {
        host_need_args(ntok, 0, 0, "free");
        cmd_free();
    } else if (strcmp(cmd, "do_step") == 0) {
        double t, h;
        int no_set = 1;
        char report[256] = "";
        host_need_args(ntok, 2, 3, "do_step <t> <h> [<noSetFMUStatePriorToCurrentPoint 0|1>]");
        host_need_instance();
        t = host_parse_double(H.tok[1], "do_step t");
        h = host_parse_double(H.tok[2], "do_step h");
        if (ntok > 3)
            no_set = host_parse_bool(H.tok[3]);
        host_fn(CALL_DO_STEP);
        s = host_check(ops->do_step(t, h, no_set, report, sizeof report), ops->names[CALL_DO_STEP]);
        printf("do_step %s%s\n", host_status_name(s), report);
    } else if (strcmp(cmd, "trace") == 0 || strcmp(cmd, "trace_me") == 0) {
        int me = strcmp(cmd, "trace_me") == 0;
        host_need_args(ntok, 4, me ? 5 : 4,
                       me ? "trace_me <file> <n_inputs> <in_vrs|-> <out_vrs|-> [events_after|events_first]"
                          : "trace <file> <n_inputs> <in_vrs|-> <out_vrs|->");
        host_trace(ntok, me);
    } else if (strcmp(cmd, "set_time") == 0) {
        double t;
        host_need_args(ntok, 1, 1, "set_time <t>");
        host_need_instance();
        t = host_parse_double(H.tok[1], "set_time t");
        host_fn(CALL_SET_TIME);
        s = host_check(ops->set_time(t), ops->names[CALL_SET_TIME]);
        printf("set_time %s\n", host_status_name(s));
    } else if (strcmp(cmd, "get_event_indicators") == 0) {
        host_need_args(ntok, 1, 1, "get_event_indicators <ni>");
        cmd_get_vector(CALL_GET_EVENT_INDICATORS, "indicator", H.tok[1]);
    } else if (strcmp(cmd, "get_continuous_states") == 0) {
        host_need_args(ntok, 1, 1, "get_continuous_states <nx>");
        cmd_get_vector(CALL_GET_CONTINUOUS_STATES, "x", H.tok[1]);
    } else if (strcmp(cmd, "get_derivatives") == 0) {
        host_need_args(ntok, 1, 1, "get_derivatives <nx>");
        cmd_get_vector(CALL_GET_DERIVATIVES, "der", H.tok[1]);
    } else if (strcmp(cmd, ops->new_discrete_states_command) == 0) {
        host_need_args(ntok, 0, 0, cmd);
        cmd_new_discrete_states();
    } else if (strcmp(cmd, "completed_integrator_step") == 0) {
        host_need_args(ntok, 0, 1, "completed_integrator_step [<noSetFMUStatePriorToCurrentPoint 0|1>]");
        cmd_completed_integrator_step(ntok);
    } else if (strcmp(cmd, "get_state") == 0 || strcmp(cmd, "set_state") == 0 || strcmp(cmd, "free_state") == 0) {
        char usage[32];
        snprintf(usage, sizeof usage, "%s <slot>", cmd);
        host_need_args(ntok, 1, 1, usage);
        cmd_state(cmd, host_parse_slot(H.tok[1]));
    } else if (strcmp(cmd, "serialize") == 0) {
        host_need_args(ntok, 2, 2, "serialize <slot> <file>");
        cmd_serialize(host_parse_slot(H.tok[1]), H.tok[2]);
    } else if (strcmp(cmd, "deserialize") == 0) {
        host_need_args(ntok, 2, 2, "deserialize <slot> <file>");
        cmd_deserialize(host_parse_slot(H.tok[1]), H.tok[2]);
    } else if (strcmp(cmd, "directional_derivative") == 0) {
        host_need_args(ntok, 3, 3, "directional_derivative <unknown_vrs> <known_vrs> <seed,..>");
        cmd_directional_derivative();
    } else if (strcmp(cmd, "cycle") == 0) {
        host_need_args(ntok, 1, 2, "cycle <n> [<name>]");
        cmd_cycle(host_parse_long(H.tok[1], 0, 100000000, "cycle n"), ntok > 2 ? H.tok[2] : "cycle");
    } else if (strcmp(cmd, "time_load") == 0) {
        host_need_args(ntok, 0, 1, "time_load [<name>]");
        cmd_time_load(ntok > 1 ? H.tok[1] : "time_load");
    } else if (strcmp(cmd, "set_debug_logging") == 0) {
        int on;
        host_need_args(ntok, 1, 1000000, "set_debug_logging <0|1> [<category> ...]");
        host_need_instance();
        on = host_parse_bool(H.tok[1]);
        host_fn(CALL_SET_DEBUG_LOGGING);
        s = host_check(ops->set_debug_logging(on, ntok - 2, ntok > 2 ? (const char *const *)&H.tok[2] : NULL),
                       ops->names[CALL_SET_DEBUG_LOGGING]);
        printf("set_debug_logging %s\n", host_status_name(s));
    } else if (strcmp(cmd, "echo") == 0) {
        for (size_t k = 1; k < ntok; k++)
            printf(k == 1 ? "%s" : " %s", H.tok[k]);
        printf("\n");
    } else {
        return 0;
    }
    return 1;
}
