/* FMI 2.0 Co-Simulation status shim of the ClearanceWearJoint FMU.
 *
 * pythonfmu 0.7 returns fmi2Fatal for every Python exception.  This library is the
 * FMU's binary: it forwards every fmi2 call to pythonfmu's binary (WRAPPED_LIBRARY,
 * next to this file) and turns fmi2Fatal into fmi2Error when the Python slave
 * called wearjoint_shim_flag_error() during the call (an ordinary error such as a
 * bad parameter, already logged by the slave with fmi2Error).  pythonfmu's
 * "Fatal py exception" echo of such an error is not passed on.
 *
 * The host's loggingOn only controls messages below fmi2Error: pythonfmu always
 * runs with logging on, so that error messages reach the host in any case.
 *
 * Built by wearjoint/fmu/build_pythonfmu.py: gcc -shared -fPIC -O2 -fvisibility=hidden
 * -DWRAPPED_LIBRARY='"<file name>"' with the FMI 2.0 headers on the include path.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#ifndef WRAPPED_LIBRARY
#error "define WRAPPED_LIBRARY, the file name of pythonfmu's binary next to this library"
#endif

/* The fmi2 functions forwarded to pythonfmu's binary (looked up at fmi2Instantiate). */
#define FORWARDED(X) X(SetDebugLogging) X(Instantiate) X(FreeInstance) X(SetupExperiment) \
    X(EnterInitializationMode) X(ExitInitializationMode) X(Terminate) X(Reset) \
    X(GetReal) X(GetInteger) X(GetBoolean) X(GetString) X(SetReal) X(SetInteger) X(SetBoolean) X(SetString) \
    X(GetFMUstate) X(SetFMUstate) X(FreeFMUstate) X(SerializedFMUstateSize) X(SerializeFMUstate) \
    X(DeSerializeFMUstate) X(GetDirectionalDerivative) X(SetRealInputDerivatives) X(GetRealOutputDerivatives) \
    X(DoStep) X(CancelStep) X(GetStatus) X(GetRealStatus) X(GetIntegerStatus) X(GetBooleanStatus) X(GetStringStatus)

typedef struct {
    fmi2Component wrapped;            /* pythonfmu's instance */
    void *library;                    /* dlopen handle of WRAPPED_LIBRARY, one per instance */
    fmi2CallbackFunctions host;       /* the host's callbacks */
    fmi2CallbackFunctions callbacks;  /* given to pythonfmu: shim logger, environment = this instance */
    fmi2Boolean host_logging_on;
#define FUNCTION_POINTER(name) fmi2##name##TYPE *name;
    struct { FORWARDED(FUNCTION_POINTER) } fn;
#undef FUNCTION_POINTER
} Instance;

/* Absolute path of WRAPPED_LIBRARY, found when this library is loaded ("" if not found). */
static char wrapped_path[PATH_MAX];

/* Set by the Python slave (through ctypes, in the calling thread) just before it raises. */
static _Thread_local int error_flagged;

__attribute__((visibility("default"))) void wearjoint_shim_flag_error(void)
{
    error_flagged = 1;
}

__attribute__((constructor)) static void find_wrapped_library(void)
{
    Dl_info info;
    if (!dladdr((void *)&find_wrapped_library, &info) || info.dli_fname == NULL)
        return;
    char *self = realpath(info.dli_fname, NULL);  /* the host may have used a relative path */
    if (self == NULL)
        return;
    char *slash = strrchr(self, '/');
    int written = snprintf(wrapped_path, sizeof wrapped_path, "%.*s/%s", (int)(slash - self), self, WRAPPED_LIBRARY);
    if (written < 0 || (size_t)written >= sizeof wrapped_path)
        wrapped_path[0] = '\0';
    free(self);
}

/* The status of the finished call: fmi2Error instead of fmi2Fatal if the slave flagged an error. */
static fmi2Status settle(fmi2Status status)
{
    int flagged = error_flagged;
    error_flagged = 0;
    return (status == fmi2Fatal && flagged) ? fmi2Error : status;
}

/* pythonfmu passes complete messages (no format arguments), so they are forwarded unchanged. */
static void shim_logger(fmi2ComponentEnvironment environment, fmi2String instance_name, fmi2Status status,
                        fmi2String category, fmi2String message, ...)
{
    const Instance *inst = environment;
    if (status == fmi2Fatal && error_flagged)
        return;  /* pythonfmu's echo of the exception the slave has logged as an error */
    if (status < fmi2Error && !inst->host_logging_on)
        return;
    inst->host.logger(inst->host.componentEnvironment, instance_name, status, category, message);
}

static void release(Instance *inst)
{
    if (inst->library != NULL)
        dlclose(inst->library);
    free(inst);
}

/* ------------------------------------------------------------------ not forwarded */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instance_name, fmi2Type fmu_type, fmi2String guid,
                              fmi2String resource_location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging_on)
{
    if (functions == NULL || functions->logger == NULL)
        return NULL;  /* nowhere to report anything (the logger is mandatory in FMI 2.0) */
    const char *log_name = instance_name != NULL ? instance_name : "";
    Instance *inst = calloc(1, sizeof *inst);
    if (inst == NULL) {
        functions->logger(functions->componentEnvironment, log_name, fmi2Error, "logStatusError",
                          "fmi2Instantiate: out of memory");
        return NULL;
    }
    inst->host = *functions;
    inst->callbacks = *functions;
    inst->callbacks.logger = shim_logger;
    inst->callbacks.componentEnvironment = inst;
    inst->host_logging_on = logging_on;

    inst->library = wrapped_path[0] != '\0' ? dlopen(wrapped_path, RTLD_NOW | RTLD_LOCAL) : NULL;
    if (inst->library == NULL) {
        functions->logger(functions->componentEnvironment, log_name, fmi2Error, "logStatusError",
                          "fmi2Instantiate: cannot load pythonfmu's binary %s next to the FMU binary: %s",
                          WRAPPED_LIBRARY, wrapped_path[0] != '\0' ? dlerror() : "FMU binary path not found");
        release(inst);
        return NULL;
    }
#define LOOK_UP(name)                                                                                       \
    if ((inst->fn.name = (fmi2##name##TYPE *)dlsym(inst->library, "fmi2" #name)) == NULL) {                   \
        functions->logger(functions->componentEnvironment, log_name, fmi2Error, "logStatusError",                \
                          "fmi2Instantiate: %s does not export fmi2" #name, wrapped_path);                    \
        release(inst);                                                                                      \
        return NULL;                                                                                        \
    }
    FORWARDED(LOOK_UP)
#undef LOOK_UP

    inst->wrapped = inst->fn.Instantiate(instance_name, fmu_type, guid, resource_location, &inst->callbacks,
                                         visible, fmi2True);
    error_flagged = 0;
    if (inst->wrapped == NULL) {
        release(inst);
        return NULL;
    }
    return inst;
}

void fmi2FreeInstance(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return;
    inst->fn.FreeInstance(inst->wrapped);
    error_flagged = 0;
    release(inst);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean logging_on, size_t n_categories,
                               const fmi2String categories[])
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    inst->host_logging_on = logging_on;
    return settle(inst->fn.SetDebugLogging(inst->wrapped, fmi2True, n_categories, categories));
}

/* ------------------------------------------------------------------ forwarded with settle() */
#define FORWARD(name, parameters, arguments)                                  \
    fmi2Status fmi2##name parameters                                          \
    {                                                                         \
        Instance *inst = c;                                                   \
        if (inst == NULL)                                                     \
            return fmi2Error;                                                 \
        return settle(inst->fn.name arguments);                               \
    }

FORWARD(SetupExperiment,
        (fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance, fmi2Real start_time,
         fmi2Boolean stop_time_defined, fmi2Real stop_time),
        (inst->wrapped, tolerance_defined, tolerance, start_time, stop_time_defined, stop_time))
FORWARD(EnterInitializationMode, (fmi2Component c), (inst->wrapped))
FORWARD(ExitInitializationMode, (fmi2Component c), (inst->wrapped))
FORWARD(Terminate, (fmi2Component c), (inst->wrapped))
FORWARD(Reset, (fmi2Component c), (inst->wrapped))

FORWARD(GetReal, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(GetInteger, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(GetBoolean, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(GetString, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(SetReal, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(SetInteger, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(SetBoolean, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(SetString, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]),
        (inst->wrapped, vr, nvr, value))

FORWARD(GetFMUstate, (fmi2Component c, fmi2FMUstate *state), (inst->wrapped, state))
FORWARD(SetFMUstate, (fmi2Component c, fmi2FMUstate state), (inst->wrapped, state))
FORWARD(FreeFMUstate, (fmi2Component c, fmi2FMUstate *state), (inst->wrapped, state))
FORWARD(SerializedFMUstateSize, (fmi2Component c, fmi2FMUstate state, size_t *size), (inst->wrapped, state, size))
FORWARD(SerializeFMUstate, (fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size),
        (inst->wrapped, state, bytes, size))
FORWARD(DeSerializeFMUstate, (fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state),
        (inst->wrapped, bytes, size, state))

FORWARD(GetDirectionalDerivative,
        (fmi2Component c, const fmi2ValueReference unknown[], size_t n_unknown, const fmi2ValueReference known[],
         size_t n_known, const fmi2Real dv_known[], fmi2Real dv_unknown[]),
        (inst->wrapped, unknown, n_unknown, known, n_known, dv_known, dv_unknown))
FORWARD(SetRealInputDerivatives,
        (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer order[], const fmi2Real value[]),
        (inst->wrapped, vr, nvr, order, value))
FORWARD(GetRealOutputDerivatives,
        (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer order[], fmi2Real value[]),
        (inst->wrapped, vr, nvr, order, value))

FORWARD(DoStep, (fmi2Component c, fmi2Real current_time, fmi2Real step_size, fmi2Boolean no_set_state_before),
        (inst->wrapped, current_time, step_size, no_set_state_before))
FORWARD(CancelStep, (fmi2Component c), (inst->wrapped))
FORWARD(GetStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Status *value), (inst->wrapped, kind, value))
FORWARD(GetRealStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Real *value), (inst->wrapped, kind, value))
FORWARD(GetIntegerStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Integer *value),
        (inst->wrapped, kind, value))
FORWARD(GetBooleanStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value),
        (inst->wrapped, kind, value))
FORWARD(GetStringStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2String *value),
        (inst->wrapped, kind, value))
