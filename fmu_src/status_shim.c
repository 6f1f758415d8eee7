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
 * Native path: once initialised, the slave attaches its joint's arrays and the
 * numba cfuncs of wearjoint/native.py (wearjoint_shim_attach_native, during a
 * forwarded call).  setReal of inputs, getReal of forces, diagnostics, inputs,
 * parameters and wear depths, and doStep are then answered here without entering
 * Python, on the same arrays and kernels the slave uses; everything else, and any
 * call the native path cannot answer in full (non-finite values, other variables,
 * the native flag cleared by the slave), goes to the slave as before.
 *
 * Built by wearjoint/fmu_build.py: gcc -shared -fPIC -O2 -fvisibility=hidden
 * -DWRAPPED_LIBRARY='"<file name>"' with the FMI 2.0 headers on the include path.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
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

/* ------------------------------------------------------------------ native path
 * Layout shared with fmu_src/ClearanceWearJoint.py (_NativePath, a ctypes Structure). */
typedef int32_t EvaluateFunction(double *kinematics, double *joint_parameters, double *cos_phi, double *sin_phi,
                                 double *wear_depth, double *block_min, double *memory, double *result, void *mask,
                                 int64_t n_points, int64_t n_blocks);
typedef int32_t AdvanceFunction(double *kinematics, double *joint_parameters, double *cos_phi, double *sin_phi,
                                double *wear_depth, double *block_min, double *memory, double *result, void *mask,
                                double *work, int64_t n_points, int64_t n_blocks, double dt);

enum { FLAG_NATIVE, FLAG_FORCES_STALE, FLAG_WEAR_SUMMARY_STALE, FLAG_TIME };   /* flags[] */
enum { SOURCE_SLAVE = -1, SOURCE_STORE, SOURCE_RESULT, SOURCE_WEAR_DEPTH };     /* read_source[] */

typedef struct {
    double *flags;                    /* 1.0 / 0.0 flags and the time, written by both sides */
    double *store;                    /* the slave's Real values by value reference; inputs first */
    const int32_t *read_source;       /* per value reference: where getReal finds it (SOURCE_*) */
    const int32_t *read_index;        /* ... and at which index */
    uint32_t n_variables;
    uint32_t n_inputs;                /* value references 0 .. n_inputs - 1 are the kinematic inputs */
    double *joint_parameters, *cos_phi, *sin_phi, *wear_depth, *block_min, *memory, *result;
    void *mask;
    double *work;                     /* scratch of the wear kernels (N_d doubles), not state */
    int64_t n_points, n_blocks;
    EvaluateFunction *evaluate;
    AdvanceFunction *advance;
} NativePath;

typedef struct {
    fmi2Component wrapped;            /* pythonfmu's instance */
    void *library;                    /* dlopen handle of WRAPPED_LIBRARY, one per instance */
    fmi2CallbackFunctions host;       /* the host's callbacks */
    fmi2CallbackFunctions callbacks;  /* given to pythonfmu: shim logger, environment = this instance */
    fmi2Boolean host_logging_on;
    int has_native;                   /* native path attached */
    NativePath native;
#define FUNCTION_POINTER(name) fmi2##name##TYPE *name;
    struct { FORWARDED(FUNCTION_POINTER) } fn;
#undef FUNCTION_POINTER
} Instance;

/* Absolute path of WRAPPED_LIBRARY, found when this library is loaded ("" if not found). */
static char wrapped_path[PATH_MAX];

/* Set by the Python slave (through ctypes, in the calling thread) just before it raises. */
static _Thread_local int error_flagged;

/* The instance whose forwarded call is running in this thread (for wearjoint_shim_attach_native). */
static _Thread_local void *current_instance;

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

/* Called by the slave during a forwarded call: answer the hot calls natively from now on
 * (the arrays must live as long as the instance, or until the next attach).  0 on success. */
__attribute__((visibility("default"))) int wearjoint_shim_attach_native(const NativePath *path)
{
    Instance *inst = current_instance;
    if (inst == NULL || path == NULL)
        return -1;
    inst->native = *path;
    inst->has_native = 1;
    return 0;
}

static const NativePath *native_path(const Instance *inst)
{
    return inst->has_native && inst->native.flags[FLAG_NATIVE] == 1.0 ? &inst->native : NULL;
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
static fmi2Status forward_end(fmi2Status status)
{
    current_instance = NULL;
    return settle(status);
}

#define FORWARD_CALL(name, arguments) (current_instance = inst, forward_end(inst->fn.name arguments))

#define FORWARD(name, parameters, arguments)                                  \
    fmi2Status fmi2##name parameters                                          \
    {                                                                         \
        Instance *inst = c;                                                   \
        if (inst == NULL)                                                     \
            return fmi2Error;                                                 \
        return FORWARD_CALL(name, arguments);                                 \
    }

FORWARD(SetupExperiment,
        (fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance, fmi2Real start_time,
         fmi2Boolean stop_time_defined, fmi2Real stop_time),
        (inst->wrapped, tolerance_defined, tolerance, start_time, stop_time_defined, stop_time))
FORWARD(EnterInitializationMode, (fmi2Component c), (inst->wrapped))
FORWARD(ExitInitializationMode, (fmi2Component c), (inst->wrapped))
FORWARD(Terminate, (fmi2Component c), (inst->wrapped))
FORWARD(Reset, (fmi2Component c), (inst->wrapped))

FORWARD(GetInteger, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(GetBoolean, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]),
        (inst->wrapped, vr, nvr, value))
FORWARD(GetString, (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]),
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

FORWARD(CancelStep, (fmi2Component c), (inst->wrapped))
FORWARD(GetStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Status *value), (inst->wrapped, kind, value))
FORWARD(GetRealStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Real *value), (inst->wrapped, kind, value))
FORWARD(GetIntegerStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Integer *value),
        (inst->wrapped, kind, value))
FORWARD(GetBooleanStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value),
        (inst->wrapped, kind, value))
FORWARD(GetStringStatus, (fmi2Component c, const fmi2StatusKind kind, fmi2String *value),
        (inst->wrapped, kind, value))

/* ------------------------------------------------------------------ native when possible */
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const NativePath *p = native_path(inst);
    if (p != NULL) {
        size_t i = 0;
        while (i < nvr && vr[i] < p->n_inputs && isfinite(value[i]))
            i++;
        if (i == nvr) {  /* finite kinematic inputs only */
            for (i = 0; i < nvr; i++)
                p->store[vr[i]] = value[i];
            p->flags[FLAG_FORCES_STALE] = 1.0;
            return fmi2OK;
        }
    }
    return FORWARD_CALL(SetReal, (inst->wrapped, vr, nvr, value));
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const NativePath *p = native_path(inst);
    if (p != NULL) {
        int needs_forces = 0;
        size_t i = 0;
        for (; i < nvr && vr[i] < p->n_variables && p->read_source[vr[i]] != SOURCE_SLAVE; i++)
            needs_forces |= p->read_source[vr[i]] == SOURCE_RESULT;
        if (i == nvr) {
            if (needs_forces && p->flags[FLAG_FORCES_STALE] != 0.0) {
                p->evaluate(p->store, p->joint_parameters, p->cos_phi, p->sin_phi, p->wear_depth, p->block_min,
                            p->memory, p->result, p->mask, p->n_points, p->n_blocks);
                p->flags[FLAG_FORCES_STALE] = 0.0;
            }
            for (i = 0; i < nvr; i++) {
                int32_t index = p->read_index[vr[i]];
                switch (p->read_source[vr[i]]) {
                case SOURCE_RESULT: value[i] = p->result[index]; break;
                case SOURCE_WEAR_DEPTH: value[i] = p->wear_depth[index]; break;
                default: value[i] = p->store[index]; break;
                }
            }
            return fmi2OK;
        }
    }
    return FORWARD_CALL(GetReal, (inst->wrapped, vr, nvr, value));
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real current_time, fmi2Real step_size, fmi2Boolean no_set_state_before)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const NativePath *p = native_path(inst);
    if (p != NULL && isfinite(step_size) && step_size >= 0.0) {
        if (p->advance(p->store, p->joint_parameters, p->cos_phi, p->sin_phi, p->wear_depth, p->block_min,
                       p->memory, p->result, p->mask, p->work, p->n_points, p->n_blocks, step_size))
            p->flags[FLAG_WEAR_SUMMARY_STALE] = 1.0;
        p->flags[FLAG_TIME] = current_time + step_size;
        p->flags[FLAG_FORCES_STALE] = 1.0;
        return fmi2OK;
    }
    return FORWARD_CALL(DoStep, (inst->wrapped, current_time, step_size, no_set_state_before));
}
