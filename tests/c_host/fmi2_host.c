/*
 * fmi2_host.c -- a minimal, dependency-free FMI 2.0 importer (Co-Simulation and Model Exchange).
 *
 * Proves that an FMU works from C with no Python on the host (and runs under valgrind).  It
 * needs only libc and libdl:
 *
 *     gcc -O2 -Wall -Wextra -I<fmi2 headers> fmi2_host.c host_common.c -o fmi2_host -ldl
 *
 * (fmpy ships the FMI 2.0 headers in <site-packages>/fmpy/c-code/.)  The script machinery, the
 * exit codes and the commands both FMI hosts share (instantiate, instantiate_me, free,
 * enter_init, exit_init, terminate, reset, do_step, trace, trace_me, the Model Exchange calls,
 * the FMU states, cycle, time_load, expect, echo, set_debug_logging) are host_common.c's and are
 * documented at the top of host_common.h; this file holds the FMI 2.0 calls.
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

#include "fmi2FunctionTypes.h"
#include "host_common.h"

/* ------------------------------------------------------------------------- */
/* The FMI 2.0 functions of the host's own commands (the shared ones: H.fn)  */

typedef struct {
    fmi2GetTypesPlatformTYPE *getTypesPlatform;
    fmi2GetVersionTYPE *getVersion;
    fmi2SetDebugLoggingTYPE *setDebugLogging;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *freeInstance;
    fmi2SetupExperimentTYPE *setupExperiment;
    fmi2EnterInitializationModeTYPE *enterInit;
    fmi2ExitInitializationModeTYPE *exitInit;
    fmi2TerminateTYPE *terminate;
    fmi2ResetTYPE *reset;
    fmi2GetRealTYPE *getReal;
    fmi2GetIntegerTYPE *getInteger;
    fmi2GetBooleanTYPE *getBoolean;
    fmi2GetStringTYPE *getString;
    fmi2SetRealTYPE *setReal;
    fmi2SetIntegerTYPE *setInteger;
    fmi2SetBooleanTYPE *setBoolean;
    fmi2SetStringTYPE *setString;
    fmi2GetFMUstateTYPE *getFMUstate;
    fmi2SetFMUstateTYPE *setFMUstate;
    fmi2FreeFMUstateTYPE *freeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *serializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *serializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *deSerializeFMUstate;
    fmi2DoStepTYPE *doStep;
    fmi2CancelStepTYPE *cancelStep;
    fmi2GetStatusTYPE *getStatus;
    fmi2GetRealStatusTYPE *getRealStatus;
    fmi2GetIntegerStatusTYPE *getIntegerStatus;
    fmi2GetBooleanStatusTYPE *getBooleanStatus;
    fmi2GetStringStatusTYPE *getStringStatus;
} Api;

static Api api;

#define REQUIRE(field, name)                                                 \
    do {                                                                     \
        if (api.field == NULL)                                               \
            host_die2("the FMU binary does not export %s", name);            \
    } while (0)

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

static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
static const fmi2CallbackFunctions callbacks_no_logger = {NULL, calloc, free, NULL, NULL};
static const fmi2CallbackFunctions callbacks_no_alloc = {logger, NULL, free, NULL, NULL};

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

/* ------------------------------------------------------------------------- */
/* FMI 2.0 commands                                                          */

static void cmd_get(size_t ntok)
{
    size_t n = ntok - 1;
    fmi2ValueReference *vr;
    fmi2Status s;
    const char *cmd = H.tok[0];
    fmi2Component comp = H.instance;
    host_need_instance();
    if (n == 0)
        host_die2("usage: %s <vr> [<vr> ...]", cmd);
    vr = host_scratch(n * sizeof *vr);
    for (size_t i = 0; i < n; i++)
        vr[i] = host_parse_vr(H.tok[i + 1]);
    if (strcmp(cmd, "get_real") == 0) {
        fmi2Real *v = host_scratch(n * sizeof *v);
        REQUIRE(getReal, "fmi2GetReal");
        s = host_check(api.getReal(comp, vr, n, v), "fmi2GetReal");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("real %u %.17g\n", vr[i], v[i]);
    } else if (strcmp(cmd, "get_integer") == 0) {
        fmi2Integer *v = host_scratch(n * sizeof *v);
        REQUIRE(getInteger, "fmi2GetInteger");
        s = host_check(api.getInteger(comp, vr, n, v), "fmi2GetInteger");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("integer %u %d\n", vr[i], v[i]);
    } else if (strcmp(cmd, "get_boolean") == 0) {
        fmi2Boolean *v = host_scratch(n * sizeof *v);
        REQUIRE(getBoolean, "fmi2GetBoolean");
        s = host_check(api.getBoolean(comp, vr, n, v), "fmi2GetBoolean");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("boolean %u %d\n", vr[i], v[i] ? 1 : 0);
    } else {
        fmi2String *v = host_scratch(n * sizeof *v);
        REQUIRE(getString, "fmi2GetString");
        s = host_check(api.getString(comp, vr, n, v), "fmi2GetString");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("string %u %s\n", vr[i], v[i] ? v[i] : "(null)");
    }
}

static void cmd_set(size_t ntok)
{
    size_t n = ntok - 1;
    fmi2ValueReference *vr;
    fmi2Status s;
    const char *cmd = H.tok[0];
    fmi2Component comp = H.instance;
    host_need_instance();
    if (n == 0)
        host_die2("usage: %s <vr>=<value> [<vr>=<value> ...]", cmd);
    vr = host_scratch(n * sizeof *vr);
    if (strcmp(cmd, "set_real") == 0) {
        fmi2Real *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = host_parse_double(host_split_assignment(H.tok[i + 1], &vr[i]), "set_real value");
        REQUIRE(setReal, "fmi2SetReal");
        s = host_check(api.setReal(comp, vr, n, v), "fmi2SetReal");
    } else if (strcmp(cmd, "set_integer") == 0) {
        fmi2Integer *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = (fmi2Integer)host_parse_long(host_split_assignment(H.tok[i + 1], &vr[i]), INT_MIN, INT_MAX,
                                                "set_integer value");
        REQUIRE(setInteger, "fmi2SetInteger");
        s = host_check(api.setInteger(comp, vr, n, v), "fmi2SetInteger");
    } else if (strcmp(cmd, "set_boolean") == 0) {
        fmi2Boolean *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = host_parse_bool(host_split_assignment(H.tok[i + 1], &vr[i]));
        REQUIRE(setBoolean, "fmi2SetBoolean");
        s = host_check(api.setBoolean(comp, vr, n, v), "fmi2SetBoolean");
    } else {
        fmi2String *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = host_split_assignment(H.tok[i + 1], &vr[i]);
        REQUIRE(setString, "fmi2SetString");
        s = host_check(api.setString(comp, vr, n, v), "fmi2SetString");
    }
    printf("%s %s\n", cmd, host_status_name(s));
}

/* call_null <function> [<what>] */
static void cmd_call_null(const char *fn, const char *what)
{
    fmi2ValueReference vr0 = 0;
    fmi2Real r = 0.0;
    fmi2Integer i = 0;
    fmi2Boolean b = fmi2False;
    fmi2String str = "";
    fmi2Status st = fmi2OK;
    fmi2FMUstate state = NULL;
    size_t size = 0;
    fmi2Byte bytes[16] = {0};
    int handled = 1;
    int is_comp = strcmp(what, "component") == 0;
    int is_values = strcmp(what, "values") == 0;
    int is_vr = strcmp(what, "vr") == 0;
    int is_state = strcmp(what, "state") == 0;
    fmi2Component c = is_comp ? NULL : H.instance;
    const fmi2ValueReference *vrp = is_vr ? NULL : &vr0;

    if (strcmp(fn, "fmi2Instantiate") == 0) {
        fmi2Component x = NULL;
        const char *name = "call_null", *guid = H.token;
        const fmi2CallbackFunctions *cb = &callbacks;
        REQUIRE(instantiate, "fmi2Instantiate");
        if (strcmp(what, "name") == 0)
            name = NULL;
        else if (strcmp(what, "guid") == 0)
            guid = NULL;
        else if (strcmp(what, "callbacks") == 0)
            cb = NULL;
        else if (strcmp(what, "logger") == 0)
            cb = &callbacks_no_logger;
        else if (strcmp(what, "alloc") == 0)
            cb = &callbacks_no_alloc;
        else
            host_die2("call_null fmi2Instantiate: <what> is one of name guid callbacks logger alloc");
        x = api.instantiate(name, fmi2CoSimulation, guid, H.resource, cb, fmi2False, fmi2True);
        printf("call_null %s %s %s\n", fn, what, x == NULL ? "null" : "nonnull");
        H.last_status = x == NULL ? fmi2OK : fmi2Error;
        if (x != NULL && api.freeInstance != NULL)
            api.freeInstance(x);
        return;
    }
    if (!is_comp && !is_values && !is_vr && !is_state)
        host_die2("call_null: <what> is one of component values vr state (or, for fmi2Instantiate, "
                  "name guid callbacks logger alloc), got '%s'", what);
    if (!is_comp)
        host_need_instance();

#define CALL(field, expr)                                                    \
    do {                                                                     \
        REQUIRE(field, fn);                                                  \
        st = (expr);                                                         \
    } while (0)
#define ONLY(cond)                                                           \
    do {                                                                     \
        if (!(cond))                                                         \
            host_die2("call_null: '%s' does not apply to %s", what, fn);     \
    } while (0)

    if (strcmp(fn, "fmi2FreeInstance") == 0) {
        ONLY(is_comp);
        REQUIRE(freeInstance, fn);
        api.freeInstance(NULL);
        st = fmi2OK;
    } else if (strcmp(fn, "fmi2SetDebugLogging") == 0) {
        ONLY(is_comp);
        CALL(setDebugLogging, api.setDebugLogging(c, fmi2True, 0, NULL));
    } else if (strcmp(fn, "fmi2SetupExperiment") == 0) {
        ONLY(is_comp);
        CALL(setupExperiment, api.setupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    } else if (strcmp(fn, "fmi2EnterInitializationMode") == 0) {
        ONLY(is_comp);
        CALL(enterInit, api.enterInit(c));
    } else if (strcmp(fn, "fmi2ExitInitializationMode") == 0) {
        ONLY(is_comp);
        CALL(exitInit, api.exitInit(c));
    } else if (strcmp(fn, "fmi2Terminate") == 0) {
        ONLY(is_comp);
        CALL(terminate, api.terminate(c));
    } else if (strcmp(fn, "fmi2Reset") == 0) {
        ONLY(is_comp);
        CALL(reset, api.reset(c));
    } else if (strcmp(fn, "fmi2DoStep") == 0) {
        ONLY(is_comp);
        CALL(doStep, api.doStep(c, 0.0, 1e-3, fmi2True));
    } else if (strcmp(fn, "fmi2CancelStep") == 0) {
        ONLY(is_comp);
        CALL(cancelStep, api.cancelStep(c));
    } else if (strcmp(fn, "fmi2GetReal") == 0) {
        ONLY(!is_state);
        CALL(getReal, api.getReal(c, vrp, 1, is_values ? NULL : &r));
    } else if (strcmp(fn, "fmi2GetInteger") == 0) {
        ONLY(!is_state);
        CALL(getInteger, api.getInteger(c, vrp, 1, is_values ? NULL : &i));
    } else if (strcmp(fn, "fmi2GetBoolean") == 0) {
        ONLY(!is_state);
        CALL(getBoolean, api.getBoolean(c, vrp, 1, is_values ? NULL : &b));
    } else if (strcmp(fn, "fmi2GetString") == 0) {
        ONLY(!is_state);
        CALL(getString, api.getString(c, vrp, 1, is_values ? NULL : &str));
    } else if (strcmp(fn, "fmi2SetReal") == 0) {
        ONLY(!is_state);
        CALL(setReal, api.setReal(c, vrp, 1, is_values ? NULL : &r));
    } else if (strcmp(fn, "fmi2SetInteger") == 0) {
        ONLY(!is_state);
        CALL(setInteger, api.setInteger(c, vrp, 1, is_values ? NULL : &i));
    } else if (strcmp(fn, "fmi2SetBoolean") == 0) {
        ONLY(!is_state);
        CALL(setBoolean, api.setBoolean(c, vrp, 1, is_values ? NULL : &b));
    } else if (strcmp(fn, "fmi2SetString") == 0) {
        ONLY(!is_state);
        CALL(setString, api.setString(c, vrp, 1, is_values ? NULL : &str));
    } else if (strcmp(fn, "fmi2GetFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(getFMUstate, api.getFMUstate(c, is_values ? NULL : &state));
    } else if (strcmp(fn, "fmi2SetFMUstate") == 0) {
        ONLY(is_comp || is_state);
        CALL(setFMUstate, api.setFMUstate(c, is_comp ? H.slots[0] : NULL));
    } else if (strcmp(fn, "fmi2FreeFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(freeFMUstate, api.freeFMUstate(c, is_values ? NULL : &state));
    } else if (strcmp(fn, "fmi2SerializedFMUstateSize") == 0) {
        ONLY(is_comp || is_values || is_state);
        CALL(serializedFMUstateSize,
             api.serializedFMUstateSize(c, is_state ? NULL : H.slots[0], is_values ? NULL : &size));
    } else if (strcmp(fn, "fmi2SerializeFMUstate") == 0) {
        ONLY(is_comp || is_values || is_state);
        CALL(serializeFMUstate, api.serializeFMUstate(c, is_state ? NULL : H.slots[0],
                                                      is_values ? NULL : bytes, sizeof bytes));
    } else if (strcmp(fn, "fmi2DeSerializeFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(deSerializeFMUstate, api.deSerializeFMUstate(c, is_values ? NULL : bytes, sizeof bytes, &state));
    } else if (strcmp(fn, "fmi2GetStatus") == 0) {
        fmi2Status v = fmi2OK;
        ONLY(is_comp || is_values);
        CALL(getStatus, api.getStatus(c, fmi2DoStepStatus, is_values ? NULL : &v));
    } else if (strcmp(fn, "fmi2GetRealStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getRealStatus, api.getRealStatus(c, fmi2LastSuccessfulTime, is_values ? NULL : &r));
    } else if (strcmp(fn, "fmi2GetIntegerStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getIntegerStatus, api.getIntegerStatus(c, fmi2DoStepStatus, is_values ? NULL : &i));
    } else if (strcmp(fn, "fmi2GetBooleanStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getBooleanStatus, api.getBooleanStatus(c, fmi2Terminated, is_values ? NULL : &b));
    } else if (strcmp(fn, "fmi2GetStringStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getStringStatus, api.getStringStatus(c, fmi2PendingStatus, is_values ? NULL : &str));
    } else {
        handled = 0;
    }
#undef CALL
#undef ONLY
    if (!handled)
        host_die2("call_null: unsupported function '%s'", fn);
    /* a state the FMU returned despite the NULL argument must not leak */
    if (state != NULL && H.instance != NULL && api.freeFMUstate != NULL && !H.fatal_seen)
        api.freeFMUstate(H.instance, &state);
    H.last_status = st;
    if (st == fmi2Fatal)
        H.fatal_seen = 1;
    printf("call_null %s %s %s\n", fn, what, host_status_name(st));
}

/* the FMI 2.0 commands; 0 if `cmd` is none of them */
static int execute(size_t ntok)
{
    const char *cmd = H.tok[0];
    fmi2Status s;

    if (strcmp(cmd, "setup") == 0) {
        double t0, stop = 0.0, tol = 0.0;
        host_need_args(ntok, 1, 3, "setup <t0> [<stop> [<tol>]]");
        host_need_instance();
        t0 = host_parse_double(H.tok[1], "setup t0");
        if (ntok > 2)
            stop = host_parse_double(H.tok[2], "setup stop");
        if (ntok > 3)
            tol = host_parse_double(H.tok[3], "setup tol");
        REQUIRE(setupExperiment, "fmi2SetupExperiment");
        s = host_check(api.setupExperiment(H.instance, ntok > 3, tol, t0, ntok > 2, stop), "fmi2SetupExperiment");
        printf("setup %s\n", host_status_name(s));
    } else if (strcmp(cmd, "set_real") == 0 || strcmp(cmd, "set_integer") == 0 ||
               strcmp(cmd, "set_boolean") == 0 || strcmp(cmd, "set_string") == 0) {
        cmd_set(ntok);
    } else if (strcmp(cmd, "get_real") == 0 || strcmp(cmd, "get_integer") == 0 ||
               strcmp(cmd, "get_boolean") == 0 || strcmp(cmd, "get_string") == 0) {
        cmd_get(ntok);
    } else if (strcmp(cmd, "call_null") == 0) {
        host_need_args(ntok, 1, 2, "call_null <fmi2Function> [<what>]");
        cmd_call_null(H.tok[1], ntok > 2 ? H.tok[2] : "component");
    } else if (strcmp(cmd, "version") == 0) {
        const char *v, *p;
        host_need_args(ntok, 0, 0, "version");
        REQUIRE(getVersion, "fmi2GetVersion");
        REQUIRE(getTypesPlatform, "fmi2GetTypesPlatform");
        v = api.getVersion();
        p = api.getTypesPlatform();
        printf("version %s %s\n", v ? v : "(null)", p ? p : "(null)");
    } else {
        return 0;
    }
    return 1;
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
    .directional_derivative = op_directional_derivative, .execute = execute,
};

int main(int argc, char **argv)
{
    return host_main(argc, argv, &OPS);
}
