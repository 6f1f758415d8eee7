/*
 * fmi2_host.c -- a minimal, dependency-free FMI 2.0 importer (Co-Simulation and Model Exchange).
 *
 * Proves that an FMU works from C with no Python on the host (and runs under valgrind).  It
 * needs only libc and libdl:
 *
 *     gcc -O2 -Wall -Wextra -I<fmi2 headers> fmi2_host*.c host_*.c -o fmi2_host -ldl
 *
 * (fmpy ships the FMI 2.0 headers in <site-packages>/fmpy/c-code/.)  The script machinery, the
 * exit codes and the commands both FMI hosts share (instantiate, instantiate_me, free,
 * enter_init, exit_init, terminate, reset, do_step, trace, trace_me, the Model Exchange calls,
 * the FMU states, cycle, time_load, expect, echo, set_debug_logging) are host_common.c's and are
 * documented at the top of host_common.h; this file holds the FMI 2.0 calls, fmi2_host_commands.c
 * the FMI 2.0 host's own commands below (fmi2_host.h).
 *
 * Usage
 *     fmi2_host [--no-unload] [--model-exchange] <fmu_dir> <model_identifier> <guid> <script_file>
 *
 *   <fmu_dir>          an unzipped FMU; the binary loaded is
 *                      <fmu_dir>/binaries/linux64/<model_identifier>.so
 *   <script_file>      one command per line ("-" reads stdin); blank lines and
 *                      lines whose first word starts with '#' are ignored
 *   --no-unload        do not dlclose() the binary at exit
 *   --model-exchange   `instantiate`, `cycle` and `time_load` use fmi2ModelExchange
 *
 * Output
 *   stdout  results, deterministic for a deterministic FMU (status lines,
 *           values, trace rows), so two runs can be compared byte for byte
 *   stderr  the FMU's log as "LOG <status> <category>: <message>", the host's
 *           diagnostics ("fmi2_host: ...") and everything measured from the
 *           machine: trace_seconds, startup_seconds, rss_kb_before/after
 *
 *   Numbers are printed with %.17g (round-trips a double bit for bit).
 *   Status names: ok warning discard error fatal pending.
 *
 * Exit codes
 *   0  script completed
 *   1  FMI failure: a call returned discard/error/fatal/pending and the next
 *      script line was not an `expect`, or an `expect` did not match
 *   2  bad input to the host itself: usage, unreadable script / data file,
 *      syntax error, missing binary or missing fmi2 symbol, no instance
 *
 * Every FMI status is checked: a status other than ok/warning must be
 * acknowledged by an `expect <status>` on the next script line, otherwise the
 * run stops with exit code 1.  On every exit path the host frees what it
 * allocated: FMU states still held in slots (fmi2FreeFMUstate), the instance
 * (fmi2FreeInstance -- skipped once any call returned fatal), the library.
 *
 * FMI 2.0 commands (besides the shared ones; <vr> is an unsigned value reference)
 *   instantiate / instantiate_me  fmi2Instantiate(fmi2CoSimulation / fmi2ModelExchange,
 *                                 resource URI file://<abs fmu_dir>/resources,
 *                                 visible=0, loggingOn=1)
 *   setup <t0> [<stop> [<tol>]]   fmi2SetupExperiment; prints "setup <status>"
 *   set_real <vr>=<value> ...     also set_integer, set_boolean (0/1/true/
 *                                 false), set_string (value without blanks);
 *                                 prints "<command> <status>"
 *   get_real <vr> ...             also get_integer, get_boolean, get_string;
 *                                 prints "<command> <status>" and, if ok or
 *                                 warning, one line per vr:
 *                                 "real <vr> <%.17g>" | "integer <vr> <d>" |
 *                                 "boolean <vr> <0|1>" | "string <vr> <s>"
 *   cycle, time_load              initialize = setup 0, enter_init, exit_init
 *   call_null <fmi2Function> [<what>]
 *                                 calls one function with NULL arguments and
 *                                 prints "call_null <fmi2Function> <what>
 *                                 <status>" (fmi2Instantiate: "... null" or
 *                                 "... nonnull", nonnull counts as error and
 *                                 the instance is freed).  A failure status
 *                                 here is the expected outcome: it needs no
 *                                 `expect` (but `expect` may check it).
 *                                 <what>, default "component":
 *                                   component  NULL fmi2Component, other args
 *                                              valid (every function with a
 *                                              component; fmi2FreeInstance(NULL)
 *                                              must merely not crash)
 *                                   values     NULL value array / NULL out
 *                                              pointer (fmi2Get*, fmi2Set*,
 *                                              fmi2GetFMUstate(c, NULL),
 *                                              fmi2FreeFMUstate(c, NULL),
 *                                              fmi2SerializedFMUstateSize
 *                                              size pointer, fmi2SerializeFMUstate
 *                                              and fmi2DeSerializeFMUstate
 *                                              buffer, fmi2Get*Status)
 *                                   vr         NULL value-reference array
 *                                              with nvr=1 (fmi2Get* and fmi2Set*)
 *                                   state      NULL fmi2FMUstate
 *                                              (fmi2SetFMUstate,
 *                                              fmi2SerializedFMUstateSize,
 *                                              fmi2SerializeFMUstate)
 *                                   name|guid|callbacks|logger|alloc
 *                                              for fmi2Instantiate: NULL
 *                                              instanceName / GUID / callback
 *                                              struct / logger / allocateMemory
 *                                 With values/vr/state the host's own instance
 *                                 is used (instantiate it first); value
 *                                 reference 0 and nvr=1 are passed.
 *   version                       prints "version <fmi2GetVersion> <fmi2GetTypesPlatform>"
 */
#define _GNU_SOURCE
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_host.h"

Api api;

/* a function of the shared table, typed; exit 2 if the binary lacks it */
#define FN(call, type) ((type *)host_fn(call))

/* ------------------------------------------------------------------------- */
/* Callbacks given to the FMU                                                */

static void logger(fmi2ComponentEnvironment env, fmi2String instance_name, fmi2Status status,
                   fmi2String category, fmi2String message, ...)
{
    char small[1024];
    char *buf = small;
    va_list ap;
    int n;
    (void)env;
    (void)instance_name;
    if (message == NULL)
        message = "(null message)";
    va_start(ap, message);
    n = vsnprintf(small, sizeof small, message, ap);
    va_end(ap);
    if (n < 0) {
        snprintf(small, sizeof small, "(unformattable message: %s)", message);
    } else if ((size_t)n >= sizeof small) {
        buf = malloc((size_t)n + 1);
        if (buf != NULL) {
            va_start(ap, message);
            vsnprintf(buf, (size_t)n + 1, message, ap);
            va_end(ap);
        } else {
            buf = small; /* truncated */
        }
    }
    host_log(status, category, buf);
    if (buf != small)
        free(buf);
}

const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
const fmi2CallbackFunctions callbacks_no_logger = {NULL, calloc, free, NULL, NULL};
const fmi2CallbackFunctions callbacks_no_alloc = {logger, NULL, free, NULL, NULL};

/* ------------------------------------------------------------------------- */
/* The shared commands' calls (host_common.h)                                */

static const char *const NAMES[N_CALLS] = {
    [CALL_INSTANTIATE_CS] = "fmi2Instantiate", [CALL_INSTANTIATE_ME] = "fmi2Instantiate",
    [CALL_FREE_INSTANCE] = "fmi2FreeInstance", [CALL_SET_DEBUG_LOGGING] = "fmi2SetDebugLogging",
    [CALL_SETUP_EXPERIMENT] = "fmi2SetupExperiment", [CALL_ENTER_INIT] = "fmi2EnterInitializationMode",
    [CALL_EXIT_INIT] = "fmi2ExitInitializationMode", [CALL_TERMINATE] = "fmi2Terminate",
    [CALL_RESET] = "fmi2Reset", [CALL_SET_REALS] = "fmi2SetReal", [CALL_GET_REALS] = "fmi2GetReal",
    [CALL_DO_STEP] = "fmi2DoStep", [CALL_SET_TIME] = "fmi2SetTime",
    [CALL_GET_EVENT_INDICATORS] = "fmi2GetEventIndicators", [CALL_ENTER_EVENT_MODE] = "fmi2EnterEventMode",
    [CALL_NEW_DISCRETE_STATES] = "fmi2NewDiscreteStates",
    [CALL_ENTER_CONTINUOUS_TIME_MODE] = "fmi2EnterContinuousTimeMode",
    [CALL_COMPLETED_INTEGRATOR_STEP] = "fmi2CompletedIntegratorStep",
    [CALL_GET_CONTINUOUS_STATES] = "fmi2GetContinuousStates", [CALL_GET_DERIVATIVES] = "fmi2GetDerivatives",
    [CALL_GET_STATE] = "fmi2GetFMUstate", [CALL_SET_STATE] = "fmi2SetFMUstate",
    [CALL_FREE_STATE] = "fmi2FreeFMUstate", [CALL_SERIALIZED_SIZE] = "fmi2SerializedFMUstateSize",
    [CALL_SERIALIZE] = "fmi2SerializeFMUstate", [CALL_DESERIALIZE] = "fmi2DeSerializeFMUstate",
    [CALL_GET_DIRECTIONAL_DERIVATIVE] = "fmi2GetDirectionalDerivative",
};

static void *op_instantiate(const char *name, const char *guid, int model_exchange)
{
    return FN(model_exchange ? CALL_INSTANTIATE_ME : CALL_INSTANTIATE_CS, fmi2InstantiateTYPE)(
        name, model_exchange ? fmi2ModelExchange : fmi2CoSimulation, guid, H.resource, &callbacks, fmi2False,
        fmi2True);
}

static void op_free_instance(void *c) { FN(CALL_FREE_INSTANCE, fmi2FreeInstanceTYPE)(c); }

/* every call of the instance alone is an fmi2Status f(fmi2Component); setup: from t0 = 0 */
static int op_call(void *c, int call)
{
    if (call == CALL_SETUP_EXPERIMENT)
        return FN(call, fmi2SetupExperimentTYPE)(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    return FN(call, fmi2TerminateTYPE)(c);
}

static int op_set_debug_logging(int on, size_t n, const char *const categories[])
{
    return FN(CALL_SET_DEBUG_LOGGING, fmi2SetDebugLoggingTYPE)(H.instance, on, n, categories);
}

static int op_set_reals(const unsigned vr[], size_t n, const double v[])
{
    return FN(CALL_SET_REALS, fmi2SetRealTYPE)(H.instance, vr, n, v);
}

static int op_get_reals(const unsigned vr[], size_t n, double v[])
{
    return FN(CALL_GET_REALS, fmi2GetRealTYPE)(H.instance, vr, n, v);
}

static int op_directional_derivative(const unsigned unknowns[], size_t n_unknowns, const unsigned knowns[],
                                     size_t n_knowns, const double seed[], double sensitivity[])
{
    return FN(CALL_GET_DIRECTIONAL_DERIVATIVE, fmi2GetDirectionalDerivativeTYPE)(H.instance, unknowns, n_unknowns,
                                                                              knowns, n_knowns, seed, sensitivity);
}

static int op_do_step(double t, double h, int no_set_prior, char *report, size_t size)
{
    (void)report; /* fmi2DoStep has no outputs */
    (void)size;
    return FN(CALL_DO_STEP, fmi2DoStepTYPE)(H.instance, t, h, no_set_prior);
}

static int op_set_time(double t) { return FN(CALL_SET_TIME, fmi2SetTimeTYPE)(H.instance, t); }

/* fmi2GetEventIndicators, fmi2GetContinuousStates, fmi2GetDerivatives: f(c, fmi2Real[], size_t) */
static int op_get_vector(int call, double v[], size_t n)
{
    return FN(call, fmi2GetDerivativesTYPE)(H.instance, v, n);
}

static int op_new_discrete_states(HostEventInfo *info)
{
    fmi2EventInfo e;
    int s;
    memset(&e, 0, sizeof e);
    s = FN(CALL_NEW_DISCRETE_STATES, fmi2NewDiscreteStatesTYPE)(H.instance, &e);
    info->needed = e.newDiscreteStatesNeeded != fmi2False;
    info->terminate = e.terminateSimulation != fmi2False;
    info->nominals_changed = e.nominalsOfContinuousStatesChanged != fmi2False;
    info->values_changed = e.valuesOfContinuousStatesChanged != fmi2False;
    info->next_time_defined = e.nextEventTimeDefined != fmi2False;
    info->next_time = e.nextEventTime;
    return s;
}

static int op_completed_integrator_step(int no_set_prior, int *enter_event_mode, int *terminate)
{
    fmi2Boolean enter = fmi2False, stop = fmi2False;
    int s = FN(CALL_COMPLETED_INTEGRATOR_STEP, fmi2CompletedIntegratorStepTYPE)(H.instance, no_set_prior, &enter,
                                                                                  &stop);
    *enter_event_mode = enter != fmi2False;
    *terminate = stop != fmi2False;
    return s;
}

static int op_get_state(void **state) { return FN(CALL_GET_STATE, fmi2GetFMUstateTYPE)(H.instance, state); }

static int op_set_state(void *state) { return FN(CALL_SET_STATE, fmi2SetFMUstateTYPE)(H.instance, state); }

static int op_free_state(void **state) { return FN(CALL_FREE_STATE, fmi2FreeFMUstateTYPE)(H.instance, state); }

static int op_serialized_size(void *state, size_t *size)
{
    return FN(CALL_SERIALIZED_SIZE, fmi2SerializedFMUstateSizeTYPE)(H.instance, state, size);
}

static int op_serialize(void *state, void *bytes, size_t size)
{
    return FN(CALL_SERIALIZE, fmi2SerializeFMUstateTYPE)(H.instance, state, (fmi2Byte *)bytes, size);
}

static int op_deserialize(const void *bytes, size_t size, void **state)
{
    return FN(CALL_DESERIALIZE, fmi2DeSerializeFMUstateTYPE)(H.instance, (const fmi2Byte *)bytes, size, state);
}

static void load(void)
{
#define LOAD(field, name) api.field = (__typeof__(api.field))host_symbol(name)
    LOAD(getTypesPlatform, "fmi2GetTypesPlatform");
    LOAD(getVersion, "fmi2GetVersion");
    LOAD(setDebugLogging, "fmi2SetDebugLogging");
    LOAD(instantiate, "fmi2Instantiate");
    LOAD(freeInstance, "fmi2FreeInstance");
    LOAD(setupExperiment, "fmi2SetupExperiment");
    LOAD(enterInit, "fmi2EnterInitializationMode");
    LOAD(exitInit, "fmi2ExitInitializationMode");
    LOAD(terminate, "fmi2Terminate");
    LOAD(reset, "fmi2Reset");
    LOAD(getReal, "fmi2GetReal");
    LOAD(getInteger, "fmi2GetInteger");
    LOAD(getBoolean, "fmi2GetBoolean");
    LOAD(getString, "fmi2GetString");
    LOAD(setReal, "fmi2SetReal");
    LOAD(setInteger, "fmi2SetInteger");
    LOAD(setBoolean, "fmi2SetBoolean");
    LOAD(setString, "fmi2SetString");
    LOAD(getFMUstate, "fmi2GetFMUstate");
    LOAD(setFMUstate, "fmi2SetFMUstate");
    LOAD(freeFMUstate, "fmi2FreeFMUstate");
    LOAD(serializedFMUstateSize, "fmi2SerializedFMUstateSize");
    LOAD(serializeFMUstate, "fmi2SerializeFMUstate");
    LOAD(deSerializeFMUstate, "fmi2DeSerializeFMUstate");
    LOAD(doStep, "fmi2DoStep");
    LOAD(cancelStep, "fmi2CancelStep");
    LOAD(getStatus, "fmi2GetStatus");
    LOAD(getRealStatus, "fmi2GetRealStatus");
    LOAD(getIntegerStatus, "fmi2GetIntegerStatus");
    LOAD(getBooleanStatus, "fmi2GetBooleanStatus");
    LOAD(getStringStatus, "fmi2GetStringStatus");
#undef LOAD
}

static const HostOps OPS = {
    .host = "fmi2_host", .source = "fmi2_host.c and host_common.h", .token_name = "guid",
    .platform = HOST_FMI2_PLATFORM, .resource_prefix = "file://", .resource_suffix = "/resources",
    .names = NAMES, .new_discrete_states_command = "new_discrete_states",
    .load = load, .instantiate = op_instantiate, .free_instance = op_free_instance, .call = op_call,
    .set_debug_logging = op_set_debug_logging, .set_reals = op_set_reals, .get_reals = op_get_reals,
    .do_step = op_do_step, .set_time = op_set_time, .get_vector = op_get_vector,
    .new_discrete_states = op_new_discrete_states, .completed_integrator_step = op_completed_integrator_step,
    .get_state = op_get_state, .set_state = op_set_state, .free_state = op_free_state,
    .serialized_size = op_serialized_size, .serialize = op_serialize, .deserialize = op_deserialize,
    .directional_derivative = op_directional_derivative, .execute = fmi2_host_execute,
};

int main(int argc, char **argv)
{
    return host_main(argc, argv, &OPS);
}
