/*
 * fmi3_host.c -- a minimal, dependency-free FMI 3.0 importer (Co-Simulation and Model Exchange).
 *
 * The FMI 3.0 twin of fmi2_host.c: the same script conventions, exit codes and shared commands
 * (host_common.c, documented at the top of host_common.h).  It needs only libc and libdl:
 *
 *     gcc -O2 -Wall -Wextra -I<fmi3 headers> fmi3_host.c host_*.c -o fmi3_host -ldl
 *
 * (fmpy ships the FMI 3.0 headers in <site-packages>/fmpy/c-code/.)
 *
 * Usage
 *     fmi3_host [--no-unload] [--model-exchange] <fmu_dir> <model_identifier> <instantiation_token>
 *               <script_file|->
 *
 *   The binary loaded is <fmu_dir>/binaries/x86_64-linux/<model_identifier>.so; the resource
 *   path given to the FMU is <abs fmu_dir>/resources/.
 *
 * FMI 3.0 commands (besides the shared ones; <vr> is an unsigned value reference)
 *   instantiate <name> [<token>]  fmi3InstantiateCoSimulation(visible=false, loggingOn=true,
 *                                 eventModeUsed=false, earlyReturnAllowed=false, no
 *                                 intermediate variables, logMessage to stderr)
 *   instantiate_me <name> [<token>]
 *                                 fmi3InstantiateModelExchange(visible=false, loggingOn=true)
 *   enter_config | exit_config    fmi3EnterConfigurationMode / fmi3ExitConfigurationMode
 *   enter_init [<t0> [<stop> [<tol>]]]
 *                                 fmi3EnterInitializationMode (startTime default 0; stop and
 *                                 tolerance defined if given); prints "enter_init <status>"
 *   set_float64 <vr>=<value> ...  also set_int64, set_uint64 (one value per vr);
 *                                 prints "<command> <status>"
 *   get_float64 <vr>[:<n>] ...    also get_int64, get_uint64; <n>: the number of values of an
 *                                 array variable (default 1), nValues = the sum.  Prints
 *                                 "<command> <status>" and, if ok or warning, one line per vr
 *                                 with its values: "float64 <vr> <v1> [<v2> ...]" (%.17g) |
 *                                 "int64 <vr> <v>" | "uint64 <vr> <v>"
 *   do_step <t> <h> [<noSet..>]   fmi3DoStep; prints "do_step <status> event_handling_needed=<0|1>
 *                                 terminate=<0|1> early_return=<0|1> last_successful_time=<t>"
 *   update_discrete_states        fmi3UpdateDiscreteStates (see new_discrete_states)
 *   get_derivatives <nx>          fmi3GetContinuousStateDerivatives
 *   get_number_of_event_indicators | get_number_of_continuous_states
 *                                 prints "<command> <status> n=<n>"
 *   cycle, time_load              initialize = enter_init 0, exit_init
 *   version                       prints "version <fmi3GetVersion>"
 */
#define _GNU_SOURCE
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3FunctionTypes.h"
#include "host_common.h"

/* the FMI 3.0 functions of this file's own commands (the shared ones: H.fn) */
static struct {
    fmi3GetVersionTYPE *getVersion;
    fmi3GetFloat64TYPE *getFloat64;
    fmi3SetFloat64TYPE *setFloat64;
    fmi3GetInt64TYPE *getInt64;
    fmi3SetInt64TYPE *setInt64;
    fmi3GetUInt64TYPE *getUInt64;
    fmi3SetUInt64TYPE *setUInt64;
    fmi3GetNumberOfEventIndicatorsTYPE *getNumberOfEventIndicators;
    fmi3GetNumberOfContinuousStatesTYPE *getNumberOfContinuousStates;
} api3;

#define FN(call, type) ((type *)host_fn(call))

static void missing(const char *name) __attribute__((noreturn));
static void missing(const char *name)
{
    host_die2("the FMU binary does not export %s", name);
}

/* a function of api3, exit 2 if the binary lacks it */
#define OWN(field, name) (api3.field != NULL ? api3.field : (missing(name), api3.field))

static void log_message(fmi3InstanceEnvironment environment, fmi3Status status, fmi3String category,
                        fmi3String message)
{
    (void)environment;
    host_log(status, category, message);
}

/* ------------------------------------------------------------------------- */
/* The shared commands' calls (host_common.h)                                */

static const char *const NAMES[N_CALLS] = {
    [CALL_INSTANTIATE_CS] = "fmi3InstantiateCoSimulation", [CALL_INSTANTIATE_ME] = "fmi3InstantiateModelExchange",
    [CALL_FREE_INSTANCE] = "fmi3FreeInstance", [CALL_SET_DEBUG_LOGGING] = "fmi3SetDebugLogging",
    [CALL_ENTER_INIT] = "fmi3EnterInitializationMode", [CALL_EXIT_INIT] = "fmi3ExitInitializationMode",
    [CALL_TERMINATE] = "fmi3Terminate", [CALL_RESET] = "fmi3Reset",
    [CALL_ENTER_CONFIG] = "fmi3EnterConfigurationMode", [CALL_EXIT_CONFIG] = "fmi3ExitConfigurationMode",
    [CALL_SET_REALS] = "fmi3SetFloat64", [CALL_GET_REALS] = "fmi3GetFloat64", [CALL_DO_STEP] = "fmi3DoStep",
    [CALL_SET_TIME] = "fmi3SetTime", [CALL_GET_EVENT_INDICATORS] = "fmi3GetEventIndicators",
    [CALL_ENTER_EVENT_MODE] = "fmi3EnterEventMode", [CALL_NEW_DISCRETE_STATES] = "fmi3UpdateDiscreteStates",
    [CALL_ENTER_CONTINUOUS_TIME_MODE] = "fmi3EnterContinuousTimeMode",
    [CALL_COMPLETED_INTEGRATOR_STEP] = "fmi3CompletedIntegratorStep",
    [CALL_GET_CONTINUOUS_STATES] = "fmi3GetContinuousStates",
    [CALL_GET_DERIVATIVES] = "fmi3GetContinuousStateDerivatives",
    [CALL_GET_STATE] = "fmi3GetFMUState", [CALL_SET_STATE] = "fmi3SetFMUState", [CALL_FREE_STATE] = "fmi3FreeFMUState",
    [CALL_SERIALIZED_SIZE] = "fmi3SerializedFMUStateSize", [CALL_SERIALIZE] = "fmi3SerializeFMUState",
    [CALL_DESERIALIZE] = "fmi3DeserializeFMUState",
    [CALL_GET_DIRECTIONAL_DERIVATIVE] = "fmi3GetDirectionalDerivative",
};

static void *op_instantiate(const char *name, const char *token, int model_exchange)
{
    if (model_exchange)
        return FN(CALL_INSTANTIATE_ME, fmi3InstantiateModelExchangeTYPE)(name, token, H.resource, fmi3False, fmi3True,
                                                                          NULL, log_message);
    return FN(CALL_INSTANTIATE_CS, fmi3InstantiateCoSimulationTYPE)(
        name, token, H.resource, fmi3False, fmi3True, fmi3False, fmi3False, NULL, 0, NULL, log_message, NULL);
}

static void op_free_instance(void *instance) { FN(CALL_FREE_INSTANCE, fmi3FreeInstanceTYPE)(instance); }

/* enter_init from t0 = 0 without stop time or tolerance; every other: fmi3Status f(fmi3Instance) */
static int op_call(void *instance, int call)
{
    if (call == CALL_ENTER_INIT)
        return FN(call, fmi3EnterInitializationModeTYPE)(instance, fmi3False, 0.0, 0.0, fmi3False, 0.0);
    return FN(call, fmi3TerminateTYPE)(instance);
}

static int op_set_debug_logging(int on, size_t n, const char *const categories[])
{
    return FN(CALL_SET_DEBUG_LOGGING, fmi3SetDebugLoggingTYPE)(H.instance, on, n, categories);
}

static int op_set_reals(const unsigned vr[], size_t n, const double v[])
{
    return FN(CALL_SET_REALS, fmi3SetFloat64TYPE)(H.instance, vr, n, v, n);
}

static int op_get_reals(const unsigned vr[], size_t n, double v[])
{
    return FN(CALL_GET_REALS, fmi3GetFloat64TYPE)(H.instance, vr, n, v, n);
}

/* scalar knowns and unknowns: nSeed = nKnowns, nSensitivity = nUnknowns */
static int op_directional_derivative(const unsigned unknowns[], size_t n_unknowns, const unsigned knowns[],
                                     size_t n_knowns, const double seed[], double sensitivity[])
{
    return FN(CALL_GET_DIRECTIONAL_DERIVATIVE, fmi3GetDirectionalDerivativeTYPE)(
        H.instance, unknowns, n_unknowns, knowns, n_knowns, seed, n_knowns, sensitivity, n_unknowns);
}

static int op_do_step(double t, double h, int no_set_prior, char *report, size_t size)
{
    fmi3Boolean event = fmi3False, terminate = fmi3False, early = fmi3False;
    fmi3Float64 last = 0.0;
    int s = FN(CALL_DO_STEP, fmi3DoStepTYPE)(H.instance, t, h, no_set_prior, &event, &terminate, &early, &last);
    if (report != NULL)
        snprintf(report, size, " event_handling_needed=%d terminate=%d early_return=%d last_successful_time=%.17g",
                 event, terminate, early, last);
    return s;
}

static int op_set_time(double t) { return FN(CALL_SET_TIME, fmi3SetTimeTYPE)(H.instance, t); }

/* fmi3GetEventIndicators, fmi3GetContinuousStates, fmi3GetContinuousStateDerivatives:
 * f(instance, fmi3Float64[], size_t) */
static int op_get_vector(int call, double v[], size_t n)
{
    return FN(call, fmi3GetContinuousStatesTYPE)(H.instance, v, n);
}

static int op_update_discrete_states(HostEventInfo *info)
{
    fmi3Boolean needed = fmi3False, terminate = fmi3False, nominals = fmi3False, values = fmi3False;
    fmi3Boolean defined = fmi3False;
    fmi3Float64 next = 0.0;
    int s = FN(CALL_NEW_DISCRETE_STATES, fmi3UpdateDiscreteStatesTYPE)(H.instance, &needed, &terminate, &nominals,
                                                                        &values, &defined, &next);
    info->needed = needed;
    info->terminate = terminate;
    info->nominals_changed = nominals;
    info->values_changed = values;
    info->next_time_defined = defined;
    info->next_time = next;
    return s;
}

static int op_completed_integrator_step(int no_set_prior, int *enter_event_mode, int *terminate)
{
    fmi3Boolean enter = fmi3False, stop = fmi3False;
    int s = FN(CALL_COMPLETED_INTEGRATOR_STEP, fmi3CompletedIntegratorStepTYPE)(H.instance, no_set_prior, &enter,
                                                                                  &stop);
    *enter_event_mode = enter;
    *terminate = stop;
    return s;
}

static int op_get_state(void **state) { return FN(CALL_GET_STATE, fmi3GetFMUStateTYPE)(H.instance, state); }

static int op_set_state(void *state) { return FN(CALL_SET_STATE, fmi3SetFMUStateTYPE)(H.instance, state); }

static int op_free_state(void **state) { return FN(CALL_FREE_STATE, fmi3FreeFMUStateTYPE)(H.instance, state); }

static int op_serialized_size(void *state, size_t *size)
{
    return FN(CALL_SERIALIZED_SIZE, fmi3SerializedFMUStateSizeTYPE)(H.instance, state, size);
}

static int op_serialize(void *state, void *bytes, size_t size)
{
    return FN(CALL_SERIALIZE, fmi3SerializeFMUStateTYPE)(H.instance, state, (fmi3Byte *)bytes, size);
}

static int op_deserialize(const void *bytes, size_t size, void **state)
{
    return FN(CALL_DESERIALIZE, fmi3DeserializeFMUStateTYPE)(H.instance, (const fmi3Byte *)bytes, size, state);
}

static void load(void)
{
#define LOAD(field, name) api3.field = (__typeof__(api3.field))host_symbol(name)
    LOAD(getVersion, "fmi3GetVersion");
    LOAD(getFloat64, "fmi3GetFloat64");
    LOAD(setFloat64, "fmi3SetFloat64");
    LOAD(getInt64, "fmi3GetInt64");
    LOAD(setInt64, "fmi3SetInt64");
    LOAD(getUInt64, "fmi3GetUInt64");
    LOAD(setUInt64, "fmi3SetUInt64");
    LOAD(getNumberOfEventIndicators, "fmi3GetNumberOfEventIndicators");
    LOAD(getNumberOfContinuousStates, "fmi3GetNumberOfContinuousStates");
#undef LOAD
}

/* ------------------------------------------------------------------------- */
/* FMI 3.0 commands                                                          */

enum { FLOAT64, INT64, UINT64 };
static const char *const TYPE_LABELS[] = {"float64", "int64", "uint64"};

static int type_of(const char *suffix)
{
    for (int k = FLOAT64; k <= UINT64; k++)
        if (strcmp(suffix, TYPE_LABELS[k]) == 0)
            return k;
    return -1;
}

static fmi3UInt64 parse_u64(const char *s, const char *what)
{
    char *end;
    unsigned long long v;
    errno = 0;
    v = strtoull(s, &end, 10);
    if (s[0] == '-' || s[0] == '+' || end == s || *end != '\0' || errno == ERANGE)
        host_die2("%s: not an unsigned 64-bit integer: '%s'", what, s);
    return (fmi3UInt64)v;
}

/* set_<type> <vr>=<value> ... : one value per vr */
static void cmd_set_values(size_t ntok, int type)
{
    const char *cmd = H.tok[0];
    size_t n = ntok - 1;
    fmi3ValueReference *vr;
    void *v;
    int s;
    host_need_instance();
    if (n == 0)
        host_die2("usage: %s <vr>=<value> [<vr>=<value> ...]", cmd);
    vr = host_scratch(n * sizeof *vr);
    v = host_scratch(n * 8); /* every type here is 8 bytes */
    for (size_t i = 0; i < n; i++) {
        const char *text = host_split_assignment(H.tok[i + 1], &vr[i]);
        if (type == FLOAT64)
            ((fmi3Float64 *)v)[i] = host_parse_double(text, cmd);
        else if (type == INT64)
            ((fmi3Int64 *)v)[i] = host_parse_long(text, INT64_MIN, INT64_MAX, cmd);
        else
            ((fmi3UInt64 *)v)[i] = parse_u64(text, cmd);
    }
    if (type == FLOAT64)
        s = host_check(OWN(setFloat64, "fmi3SetFloat64")(H.instance, vr, n, v, n),
                       "fmi3SetFloat64");
    else if (type == INT64)
        s = host_check(OWN(setInt64, "fmi3SetInt64")(H.instance, vr, n, v, n),
                       "fmi3SetInt64");
    else
        s = host_check(OWN(setUInt64, "fmi3SetUInt64")(H.instance, vr, n, v, n),
                       "fmi3SetUInt64");
    printf("%s %s\n", cmd, host_status_name(s));
}

/* get_<type> <vr>[:<n>] ... */
static void cmd_get_values(size_t ntok, int type)
{
    const char *cmd = H.tok[0];
    size_t nvr = ntok - 1, n_values = 0, k = 0;
    fmi3ValueReference *vr;
    size_t *count;
    void *v;
    int s;
    host_need_instance();
    if (nvr == 0)
        host_die2("usage: %s <vr>[:<n>] [<vr>[:<n>] ...]", cmd);
    vr = host_scratch(nvr * sizeof *vr);
    count = host_scratch(nvr * sizeof *count);
    for (size_t i = 0; i < nvr; i++) {
        char *colon = strchr(H.tok[i + 1], ':');
        count[i] = 1;
        if (colon != NULL) {
            *colon = '\0';
            count[i] = (size_t)host_parse_long(colon + 1, 0, 100000000, "value count");
        }
        vr[i] = host_parse_vr(H.tok[i + 1]);
        n_values += count[i];
    }
    v = host_scratch(n_values * 8);
    if (type == FLOAT64)
        s = OWN(getFloat64, "fmi3GetFloat64")(H.instance, vr, nvr, v, n_values);
    else if (type == INT64)
        s = OWN(getInt64, "fmi3GetInt64")(H.instance, vr, nvr, v, n_values);
    else
        s = OWN(getUInt64, "fmi3GetUInt64")(H.instance, vr, nvr, v, n_values);
    host_check(s, type == FLOAT64 ? "fmi3GetFloat64" : type == INT64 ? "fmi3GetInt64" : "fmi3GetUInt64");
    printf("%s %s\n", cmd, host_status_name(s));
    if (s > HOST_WARNING)
        return;
    for (size_t i = 0; i < nvr; i++) {
        printf("%s %u", TYPE_LABELS[type], vr[i]);
        for (size_t j = 0; j < count[i]; j++, k++) {
            if (type == FLOAT64)
                printf(" %.17g", ((const fmi3Float64 *)v)[k]);
            else if (type == INT64)
                printf(" %lld", (long long)((const fmi3Int64 *)v)[k]);
            else
                printf(" %llu", (unsigned long long)((const fmi3UInt64 *)v)[k]);
        }
        printf("\n");
    }
}

/* enter_init [<t0> [<stop> [<tol>]]] */
static void cmd_enter_init(size_t ntok)
{
    double args[3] = {0.0, 0.0, 0.0}; /* startTime, stopTime, tolerance */
    int s;
    host_need_args(ntok, 0, 3, "enter_init [<t0> [<stop> [<tol>]]]");
    host_need_instance();
    for (size_t k = 1; k < ntok; k++)
        args[k - 1] = host_parse_double(H.tok[k], "enter_init argument");
    s = FN(CALL_ENTER_INIT, fmi3EnterInitializationModeTYPE)(H.instance, ntok > 3, args[2], args[0], ntok > 2,
                                                              args[1]);
    host_check(s, NAMES[CALL_ENTER_INIT]);
    printf("enter_init %s\n", host_status_name(s));
}

/* get_number_of_event_indicators | get_number_of_continuous_states */
static void cmd_get_number(int event_indicators)
{
    size_t n = 0;
    int s;
    host_need_instance();
    if (event_indicators)
        s = OWN(getNumberOfEventIndicators, "fmi3GetNumberOfEventIndicators")(H.instance, &n);
    else
        s = OWN(getNumberOfContinuousStates, "fmi3GetNumberOfContinuousStates")(H.instance, &n);
    host_check(s, event_indicators ? "fmi3GetNumberOfEventIndicators" : "fmi3GetNumberOfContinuousStates");
    printf("%s %s n=%zu\n", H.tok[0], host_status_name(s), n);
}

/* the FMI 3.0 commands; 0 if `cmd` is none of them */
static int execute(size_t ntok)
{
    const char *cmd = H.tok[0];
    if (strncmp(cmd, "get_", 4) == 0 && type_of(cmd + 4) >= 0) {
        cmd_get_values(ntok, type_of(cmd + 4));
    } else if (strncmp(cmd, "set_", 4) == 0 && type_of(cmd + 4) >= 0) {
        cmd_set_values(ntok, type_of(cmd + 4));
    } else if (strcmp(cmd, "enter_init") == 0) {
        cmd_enter_init(ntok);
    } else if (strcmp(cmd, "get_number_of_event_indicators") == 0 ||
               strcmp(cmd, "get_number_of_continuous_states") == 0) {
        host_need_args(ntok, 0, 0, cmd);
        cmd_get_number(strcmp(cmd, "get_number_of_event_indicators") == 0);
    } else if (strcmp(cmd, "version") == 0) {
        const char *v;
        host_need_args(ntok, 0, 0, "version");
        v = OWN(getVersion, "fmi3GetVersion")();
        printf("version %s\n", v ? v : "(null)");
    } else {
        return 0;
    }
    return 1;
}

static const HostOps OPS = {
    .host = "fmi3_host", .source = "fmi3_host.c and host_common.h", .token_name = "instantiation_token",
    .platform = HOST_FMI3_PLATFORM, .resource_prefix = "", .resource_suffix = "/resources/",
    .names = NAMES, .new_discrete_states_command = "update_discrete_states",
    .load = load, .instantiate = op_instantiate, .free_instance = op_free_instance, .call = op_call,
    .set_debug_logging = op_set_debug_logging, .set_reals = op_set_reals, .get_reals = op_get_reals,
    .do_step = op_do_step, .set_time = op_set_time, .get_vector = op_get_vector,
    .new_discrete_states = op_update_discrete_states, .completed_integrator_step = op_completed_integrator_step,
    .get_state = op_get_state, .set_state = op_set_state, .free_state = op_free_state,
    .serialized_size = op_serialized_size, .serialize = op_serialize, .deserialize = op_deserialize,
    .directional_derivative = op_directional_derivative, .execute = execute,
};

int main(int argc, char **argv)
{
    return host_main(argc, argv, &OPS);
}
