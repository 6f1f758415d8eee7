/* FMI 3.0 layer of the native FMUs: Co-Simulation and Model Exchange, for every model.
 *
 * The FMI 3.0 twin of fmi2Functions.c, on the same model interface (fmu_model.h) with the same
 * semantics:
 * - Co-Simulation: no event mode, no intermediate update, fmi3DoStep never returns early;
 * - parameters are fixed at fmi3ExitInitializationMode, where the model checks them (fmi3Error
 *   with a message naming the variable and its allowed range); enumerations are read and written
 *   with fmi3GetInt64 / fmi3SetInt64;
 * - structural parameters (UInt64; ClearanceWearJoint's n_points) are set in Configuration Mode
 *   (fmi3EnterConfigurationMode .. fmi3ExitConfigurationMode, where the model applies them); an
 *   array variable (ClearanceWearJoint's wear_depth) counts its size in nValues;
 * - a step the model cannot take gives fmi3Discard (state unchanged, the instance stays in Step
 *   Mode);
 * - the FMU states are the FMI 2.0 layer's (fmu_state.c; the same serialised bytes).
 * FMI 3.0 has no memory callbacks: calloc/free.  Nothing is printed; every message goes to the
 * host's fmi3LogMessageCallback (none if it gave NULL).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fmu_model.h"
#include "model_variables.h"

typedef enum {
    MODE_INSTANTIATED, MODE_CONFIGURATION, MODE_INITIALIZATION, MODE_STEP, MODE_EVENT, MODE_CONTINUOUS,
    MODE_TERMINATED
} Mode;
static const char *const MODE_NAMES[] = {"Instantiated", "Configuration Mode", "Initialization Mode", "Step Mode",
                                         "Event Mode", "Continuous-Time Mode", "Terminated"};
#define M(mode) (1u << (mode))
#define INITIALISED (M(MODE_STEP) | M(MODE_EVENT) | M(MODE_CONTINUOUS) | M(MODE_TERMINATED))
#define READABLE (M(MODE_INITIALIZATION) | INITIALISED)
#define SETTABLE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP) | M(MODE_EVENT) | M(MODE_CONTINUOUS))

typedef struct {
    FmuModel *model;
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;
    int co_simulation;             /* 1: Co-Simulation, 0: Model Exchange */
    Mode mode;
} Instance;

/* ------------------------------------------------------------------ host callbacks */
/* FMI 3.0 has no memory callbacks: the C library's (FmuAllocateFunction / FmuReleaseFunction). */
static void *allocate(void *environment, size_t n, size_t size)
{
    (void)environment;
    return calloc(n, size);
}

static void release(void *environment, void *p)
{
    (void)environment;
    free(p);
}

/* The message as it is (an FMI 3.0 logger takes no format); nothing without a logger. */
static void log_to_host(void *environment, const char *name, int status, const char *category, const char *message)
{
    const Instance *inst = environment;
    (void)name;
    if (inst->log_message != NULL)
        inst->log_message(inst->environment, (fmi3Status)status, category, message);
}

#define LOG(inst, ...) fmu_log(model_host((inst)->model), __VA_ARGS__)

/* ------------------------------------------------------------------ checks shared by the calls */
static int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    LOG(inst, fmi3Error, "%s: not allowed in state %s (FMI 3.0 call sequence)", function,
              MODE_NAMES[inst->mode]);
    return 0;
}

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr, const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        LOG(inst, fmi3Error, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

static void variable_name(const Instance *inst, fmi3ValueReference vr, char *out, size_t size)
{
    model_variable_name(inst->model, 3, vr, out, size);
}

/* The number of values nvr Float64 value references stand for (an array counts its size);
 * 0 (logged) if one is not a Float64 variable or the count is not n_values (the argument ``count``). */
static int float64_values(const Instance *inst, const char *function, const fmi3ValueReference vr[], size_t nvr,
                          size_t n_values, const char *count)
{
    size_t needed = 0;
    for (size_t i = 0; i < nvr; i++) {
        size_t n = model_float64_count(inst->model, 3, vr[i]);
        if (n == 0) {
            char name[96];
            variable_name(inst, vr[i], name, sizeof name);
            LOG(inst, fmi3Error, "%s: %s is not a Float64 variable", function, name);
            return 0;
        }
        needed += n;
    }
    if (needed != n_values) {
        char sizes[128];
        LOG(inst, fmi3Error, "%s: %s=%zu, but the %zu value references stand for %zu values%s", function, count,
            n_values, nvr, needed, model_array_sizes(inst->model, sizes, sizeof sizes));
        return 0;
    }
    return 1;
}

/* Scalars of one value each: nValues must equal nValueReferences. */
static int scalar_values(const Instance *inst, const char *function, size_t nvr, size_t n_values)
{
    if (nvr == n_values)
        return 1;
    LOG(inst, fmi3Error, "%s: nValues=%zu for %zu scalar variables", function, n_values, nvr);
    return 0;
}

/* ------------------------------------------------------------------ lifetime */
const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean logging_on, size_t n_categories,
                               const fmi3String categories[])
{
    Instance *inst = instance;
    (void)n_categories;
    (void)categories;
    if (inst == NULL)
        return fmi3Error;
    model_host(inst->model)->logging_on = logging_on;
    return fmi3OK;
}

static Instance *instantiate(const char *function, fmi3String instance_name, fmi3String token, fmi3Boolean logging_on,
                             fmi3InstanceEnvironment environment, fmi3LogMessageCallback log_message,
                             int co_simulation)
{
    const char *problem = NULL;
    if (instance_name == NULL || instance_name[0] == '\0')
        problem = "instanceName is missing";
    else if (token == NULL || strcmp(token, MODEL_GUID) != 0)
        problem = "the instantiationToken does not match this FMU's modelDescription.xml ("
                  MODEL_GUID ")";
    if (problem != NULL) {
        if (log_message != NULL) {
            char text[512];
            snprintf(text, sizeof text, "%s: %s", function, problem);
            log_message(environment, fmi3Error, "logStatusError", text);
        }
        return NULL;
    }
    Instance *inst = calloc(1, sizeof *inst);
    if (inst == NULL) {
        if (log_message != NULL)
            log_message(environment, fmi3Error, "logStatusError", "fmi3Instantiate: out of memory");
        return NULL;
    }
    inst->environment = environment;
    inst->log_message = log_message;
    inst->co_simulation = co_simulation;
    inst->mode = MODE_INSTANTIATED;
    inst->model = model_new(instance_name, logging_on, log_to_host, allocate, release, inst);
    if (inst->model == NULL) {
        free(inst);
        return NULL;
    }
    return inst;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instance_name, fmi3String instantiation_token,
                                          fmi3String resource_path, fmi3Boolean visible, fmi3Boolean logging_on,
                                          fmi3InstanceEnvironment instance_environment,
                                          fmi3LogMessageCallback log_message)
{
    (void)resource_path;
    (void)visible;
    return instantiate("fmi3InstantiateModelExchange", instance_name, instantiation_token, logging_on,
                       instance_environment, log_message, 0);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instance_name, fmi3String instantiation_token,
                                         fmi3String resource_path, fmi3Boolean visible, fmi3Boolean logging_on,
                                         fmi3Boolean event_mode_used, fmi3Boolean early_return_allowed,
                                         const fmi3ValueReference required_intermediate_variables[],
                                         size_t n_required_intermediate_variables,
                                         fmi3InstanceEnvironment instance_environment,
                                         fmi3LogMessageCallback log_message,
                                         fmi3IntermediateUpdateCallback intermediate_update)
{
    (void)resource_path;
    (void)visible;
    (void)early_return_allowed;            /* the FMU never returns early */
    (void)required_intermediate_variables; /* nor calls intermediateUpdate */
    (void)intermediate_update;
    if (event_mode_used || n_required_intermediate_variables > 0) {
        if (log_message != NULL)
            log_message(instance_environment, fmi3Error, "logStatusError",
                        "fmi3InstantiateCoSimulation: this FMU has no event mode (hasEventMode=\"false\") and no "
                        "intermediate variables: eventModeUsed must be false and nRequiredIntermediateVariables 0");
        return NULL;
    }
    return instantiate("fmi3InstantiateCoSimulation", instance_name, instantiation_token, logging_on,
                       instance_environment, log_message, 1);
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instance_name, fmi3String instantiation_token,
                                               fmi3String resource_path, fmi3Boolean visible, fmi3Boolean logging_on,
                                               fmi3InstanceEnvironment instance_environment,
                                               fmi3LogMessageCallback log_message, fmi3ClockUpdateCallback clock_update,
                                               fmi3LockPreemptionCallback lock_preemption,
                                               fmi3UnlockPreemptionCallback unlock_preemption)
{
    (void)instance_name;
    (void)instantiation_token;
    (void)resource_path;
    (void)visible;
    (void)logging_on;
    (void)clock_update;
    (void)lock_preemption;
    (void)unlock_preemption;
    if (log_message != NULL)
        log_message(instance_environment, fmi3Error, "logStatusError",
                    "fmi3InstantiateScheduledExecution: this FMU provides Co-Simulation and Model Exchange only");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return;
    model_free(inst->model);
    free(inst);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean tolerance_defined, fmi3Float64 tolerance,
                                       fmi3Float64 start_time, fmi3Boolean stop_time_defined, fmi3Float64 stop_time)
{
    Instance *inst = instance;
    (void)tolerance_defined;
    (void)tolerance;
    (void)stop_time_defined;
    (void)stop_time;
    if (inst == NULL || !mode_is(inst, "fmi3EnterInitializationMode", M(MODE_INSTANTIATED)))
        return fmi3Error;
    if (!isfinite(start_time)) {
        LOG(inst, fmi3Error, "fmi3EnterInitializationMode: startTime=%g is invalid: allowed a finite time",
                  start_time);
        return fmi3Error;
    }
    model_set_start_time(inst->model, start_time);
    inst->mode = MODE_INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3ExitInitializationMode", M(MODE_INITIALIZATION)))
        return fmi3Error;
    if (!model_exit_initialization(inst->model, "fmi3ExitInitializationMode"))
        return fmi3Error;
    inst->mode = inst->co_simulation ? MODE_STEP : MODE_EVENT;
    return fmi3OK;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (inst->co_simulation) {
        LOG(inst, fmi3Error, "fmi3EnterEventMode: this Co-Simulation FMU has no event mode "
                  "(hasEventMode=\"false\")");
        return fmi3Error;
    }
    if (!mode_is(inst, "fmi3EnterEventMode", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi3Error;
    inst->mode = MODE_EVENT;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3Terminate", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi3Error;
    inst->mode = MODE_TERMINATED;
    return fmi3OK;
}

/* Back to Instantiated with every variable at its start value, structural parameters too. */
fmi3Status fmi3Reset(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (!model_reset(inst->model))
        return fmi3Error;
    inst->mode = MODE_INSTANTIATED;
    return fmi3OK;
}

/* ------------------------------------------------------------------ Configuration Mode: structural parameters */
fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3EnterConfigurationMode", M(MODE_INSTANTIATED)))
        return fmi3Error;
    model_enter_configuration(inst->model);
    inst->mode = MODE_CONFIGURATION;
    return fmi3OK;
}

/* Apply the structural parameters set; inputs, parameters and the time set before are kept. */
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3ExitConfigurationMode", M(MODE_CONFIGURATION)))
        return fmi3Error;
    if (!model_exit_configuration(inst->model))
        return fmi3Error;   /* (logged): the old values stay, still in Configuration Mode */
    inst->mode = MODE_INSTANTIATED;
    return fmi3OK;
}

/* ------------------------------------------------------------------ values */
fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 value[],
                          size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetFloat64", nvr, vr, value) || !mode_is(inst, "fmi3GetFloat64", READABLE) ||
        !float64_values(inst, "fmi3GetFloat64", vr, nvr, n_values, "nValues"))
        return fmi3Error;
    size_t k = 0;
    for (size_t i = 0; i < nvr; i++) {
        if (model_get_float64(inst->model, 3, vr[i], value + k, "fmi3GetFloat64") != 1)
            return fmi3Error;
        k += model_float64_count(inst->model, 3, vr[i]);
    }
    return fmi3OK;
}

/* A parameter may be set before fmi3ExitInitializationMode only. */
static int parameters_settable(const Instance *inst)
{
    return inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION;
}

/* After a set that did not succeed: -1 the variable cannot be set, -2 a parameter after
 * initialisation (logged here); 0 the model logged it. */
static fmi3Status set_failed(const Instance *inst, const char *function, fmi3ValueReference vr, const char *type,
                             int done)
{
    char name[96];
    variable_name(inst, vr, name, sizeof name);
    if (done == -1)
        LOG(inst, fmi3Error, "%s: %s is not a %s variable that can be set", function, name, type);
    else if (done == -2)
        LOG(inst, fmi3Error, "%s: parameter %s is fixed: set it before fmi3ExitInitializationMode", function, name);
    return fmi3Error;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 value[],
                          size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3SetFloat64", nvr, vr, value) || !mode_is(inst, "fmi3SetFloat64", SETTABLE) ||
        !scalar_values(inst, "fmi3SetFloat64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_float64(inst->model, 3, vr[i], value[i], parameters_settable(inst), "fmi3SetFloat64");
        if (done != 1)
            return set_failed(inst, "fmi3SetFloat64", vr[i], "Float64", done);
    }
    return fmi3OK;
}

/* The enumerations: their item values. */
fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 value[],
                        size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetInt64", nvr, vr, value) || !mode_is(inst, "fmi3GetInt64", READABLE) ||
        !scalar_values(inst, "fmi3GetInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        int64_t v = 0;
        int done = model_get_integer(inst->model, 3, vr[i], &v, "fmi3GetInt64");
        if (done == -1) {
            char name[96];
            variable_name(inst, vr[i], name, sizeof name);
            LOG(inst, fmi3Error, "fmi3GetInt64: %s is not an Enumeration variable", name);
        }
        if (done != 1)
            return fmi3Error;
        value[i] = v;
    }
    return fmi3OK;
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int64 value[],
                        size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3SetInt64", nvr, vr, value) || !mode_is(inst, "fmi3SetInt64", SETTABLE) ||
        !scalar_values(inst, "fmi3SetInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_integer(inst->model, 3, vr[i], value[i], parameters_settable(inst), "fmi3SetInt64");
        if (done != 1)
            return set_failed(inst, "fmi3SetInt64", vr[i], "Enumeration", done);
    }
    return fmi3OK;
}

/* The structural parameters: readable in every state, set in Configuration Mode. */
fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 value[],
                         size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetUInt64", nvr, vr, value) || !scalar_values(inst, "fmi3GetUInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        if (model_get_structural(inst->model, vr[i], inst->mode == MODE_CONFIGURATION, &value[i]) != 1) {
            char name[96];
            variable_name(inst, vr[i], name, sizeof name);
            LOG(inst, fmi3Error, "fmi3GetUInt64: %s is not a UInt64 variable", name);
            return fmi3Error;
        }
    }
    return fmi3OK;
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 value[],
                         size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3SetUInt64", nvr, vr, value) || !scalar_values(inst, "fmi3SetUInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_structural(inst->model, vr[i], value[i], inst->mode == MODE_CONFIGURATION,
                                        (M(inst->mode) & SETTABLE) != 0, MODE_NAMES[inst->mode], "fmi3SetUInt64");
        if (done != 1)
            return set_failed(inst, "fmi3SetUInt64", vr[i], "UInt64", done);
    }
    return fmi3OK;
}

/* The types this FMU has no variables of. */
#define NO_VARIABLES_OF_TYPE(function, type, qualifier)                                                          \
    fmi3Status function(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, qualifier type value[], \
                        size_t n_values)                                                                         \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        (void)n_values;                                                                                          \
        if (!arrays_given(inst, #function, nvr, vr, value))                                                      \
            return fmi3Error;                                                                                    \
        if (nvr == 0)                                                                                            \
            return fmi3OK;                                                                                       \
        LOG(inst, fmi3Error, "%s: this FMU has no %s variables (valueReference %u)", #function,     \
                  #type, (unsigned)vr[0]);                                                                       \
        return fmi3Error;                                                                                        \
    }

NO_VARIABLES_OF_TYPE(fmi3GetFloat32, fmi3Float32, )
NO_VARIABLES_OF_TYPE(fmi3SetFloat32, fmi3Float32, const)
NO_VARIABLES_OF_TYPE(fmi3GetInt8, fmi3Int8, )
NO_VARIABLES_OF_TYPE(fmi3SetInt8, fmi3Int8, const)
NO_VARIABLES_OF_TYPE(fmi3GetUInt8, fmi3UInt8, )
NO_VARIABLES_OF_TYPE(fmi3SetUInt8, fmi3UInt8, const)
NO_VARIABLES_OF_TYPE(fmi3GetInt16, fmi3Int16, )
NO_VARIABLES_OF_TYPE(fmi3SetInt16, fmi3Int16, const)
NO_VARIABLES_OF_TYPE(fmi3GetUInt16, fmi3UInt16, )
NO_VARIABLES_OF_TYPE(fmi3SetUInt16, fmi3UInt16, const)
NO_VARIABLES_OF_TYPE(fmi3GetInt32, fmi3Int32, )
NO_VARIABLES_OF_TYPE(fmi3SetInt32, fmi3Int32, const)
NO_VARIABLES_OF_TYPE(fmi3GetUInt32, fmi3UInt32, )
NO_VARIABLES_OF_TYPE(fmi3SetUInt32, fmi3UInt32, const)
NO_VARIABLES_OF_TYPE(fmi3GetBoolean, fmi3Boolean, )
NO_VARIABLES_OF_TYPE(fmi3SetBoolean, fmi3Boolean, const)
NO_VARIABLES_OF_TYPE(fmi3GetString, fmi3String, )
NO_VARIABLES_OF_TYPE(fmi3SetString, fmi3String, const)

/* (the unused parameters of these functions are named, for the reader; -Wno-unused-parameter) */
#define NOT_PROVIDED(function, parameters, reason)                      \
    fmi3Status function parameters                                      \
    {                                                                   \
        Instance *inst = instance;                                      \
        if (inst == NULL)                                               \
            return fmi3Error;                                           \
        LOG(inst, fmi3Error, "%s: %s", #function, reason); \
        return fmi3Error;                                               \
    }

#define NO_BINARY "this FMU has no Binary variables"
#define NO_CLOCKS "this FMU has no clocks"
NOT_PROVIDED(fmi3GetBinary,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, size_t value_sizes[],
              fmi3Binary values[], size_t n_values),
             NO_BINARY)
NOT_PROVIDED(fmi3SetBinary,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const size_t value_sizes[],
              const fmi3Binary values[], size_t n_values),
             NO_BINARY)
NOT_PROVIDED(fmi3GetClock, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock values[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetClock,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock values[]), NO_CLOCKS)
NOT_PROVIDED(fmi3GetIntervalDecimal,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 intervals[],
              fmi3IntervalQualifier qualifiers[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3GetIntervalFraction,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 counters[],
              fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3GetShiftDecimal,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 shifts[]), NO_CLOCKS)
NOT_PROVIDED(fmi3GetShiftFraction,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 counters[],
              fmi3UInt64 resolutions[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetIntervalDecimal,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 intervals[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetIntervalFraction,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 counters[],
              const fmi3UInt64 resolutions[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetShiftDecimal,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 shifts[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetShiftFraction,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 counters[],
              const fmi3UInt64 resolutions[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3ActivateModelPartition,
             (fmi3Instance instance, fmi3ValueReference clock_reference, fmi3Float64 activation_time), NO_CLOCKS)
NOT_PROVIDED(fmi3EvaluateDiscreteStates, (fmi3Instance instance),
             "providesEvaluateDiscreteStates is false for this FMU")
NOT_PROVIDED(fmi3GetNumberOfVariableDependencies,
             (fmi3Instance instance, fmi3ValueReference vr, size_t *n_dependencies),
             "providesPerElementDependencies is false for this FMU (see the ModelStructure)")
NOT_PROVIDED(fmi3GetVariableDependencies,
             (fmi3Instance instance, fmi3ValueReference dependent, size_t element_indices_of_dependent[],
              fmi3ValueReference independents[], size_t element_indices_of_independents[],
              fmi3DependencyKind dependency_kinds[], size_t n_dependencies),
             "providesPerElementDependencies is false for this FMU (see the ModelStructure)")
NOT_PROVIDED(fmi3GetAdjointDerivative,
             (fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,
              const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[], size_t n_seed,
              fmi3Float64 sensitivity[], size_t n_sensitivity),
             "providesAdjointDerivatives is false for this FMU")
NOT_PROVIDED(fmi3GetOutputDerivatives,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 orders[],
              fmi3Float64 values[], size_t n_values),
             "maxOutputDerivativeOrder is 0 for this FMU")

/* sensitivity = J seed, J the partial derivatives of the unknowns (outputs; an array counts its size) with respect
 * to the knowns (inputs). */
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,
                                        const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[],
                                        size_t n_seed, fmi3Float64 sensitivity[], size_t n_sensitivity)
{
    Instance *inst = instance;
    const char *function = "fmi3GetDirectionalDerivative";
    if (!arrays_given(inst, function, n_unknowns, unknowns, sensitivity) ||
        !arrays_given(inst, function, n_knowns, knowns, seed) || !mode_is(inst, function, READABLE) ||
        !float64_values(inst, function, unknowns, n_unknowns, n_sensitivity, "nSensitivity") ||
        !float64_values(inst, function, knowns, n_knowns, n_seed, "nSeed"))
        return fmi3Error;
    int done = model_directional_derivative(inst->model, 3, unknowns, n_unknowns, knowns, n_knowns, seed, sensitivity,
                                            function);
    if (done == -1) {
        LOG(inst, fmi3Error, "%s: providesDirectionalDerivatives is false for this FMU", function);
        return fmi3Error;
    }
    return done == 1 ? fmi3OK : fmi3Error;
}

/* ------------------------------------------------------------------ Co-Simulation */
fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (!inst->co_simulation) {
        LOG(inst, fmi3Error, "fmi3EnterStepMode: a Co-Simulation function, this is Model Exchange");
        return fmi3Error;
    }
    /* without event mode the instance is in Step Mode from fmi3ExitInitializationMode on */
    return mode_is(inst, "fmi3EnterStepMode", M(MODE_STEP)) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 current_time, fmi3Float64 step_size,
                      fmi3Boolean no_set_state_prior, fmi3Boolean *event_handling_needed,
                      fmi3Boolean *terminate_simulation, fmi3Boolean *early_return, fmi3Float64 *last_successful_time)
{
    Instance *inst = instance;
    (void)no_set_state_prior;
    if (inst == NULL || !mode_is(inst, "fmi3DoStep", M(MODE_STEP)))
        return fmi3Error;
    if (event_handling_needed == NULL || terminate_simulation == NULL || early_return == NULL ||
        last_successful_time == NULL) {
        LOG(inst, fmi3Error, "fmi3DoStep: NULL output pointer");
        return fmi3Error;
    }
    *event_handling_needed = fmi3False;
    *terminate_simulation = fmi3False;
    *early_return = fmi3False;
    *last_successful_time = model_time(inst->model);
    if (!isfinite(current_time)) {
        LOG(inst, fmi3Error, "fmi3DoStep: currentCommunicationPoint=%g is not finite", current_time);
        return fmi3Discard;
    }
    int status = model_do_step(inst->model, current_time, step_size, "fmi3DoStep");
    *last_successful_time = model_time(inst->model);
    return (fmi3Status)status;
}

/* ------------------------------------------------------------------ Model Exchange */
/* An event: the model's update (ClearanceWearJoint: the contact-onset bookkeeping). */
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discrete_states_need_update,
                                    fmi3Boolean *terminate_simulation, fmi3Boolean *nominals_changed,
                                    fmi3Boolean *values_changed, fmi3Boolean *next_event_time_defined,
                                    fmi3Float64 *next_event_time)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3UpdateDiscreteStates", M(MODE_EVENT)))
        return fmi3Error;
    if (discrete_states_need_update == NULL || terminate_simulation == NULL || nominals_changed == NULL ||
        values_changed == NULL || next_event_time_defined == NULL || next_event_time == NULL) {
        LOG(inst, fmi3Error, "fmi3UpdateDiscreteStates: NULL output pointer");
        return fmi3Error;
    }
    *discrete_states_need_update = fmi3False;
    *terminate_simulation = fmi3False;
    *nominals_changed = fmi3False;
    *values_changed = fmi3False;
    *next_event_time_defined = fmi3False;
    *next_event_time = 0.0;
    return model_event_update(inst->model, "fmi3UpdateDiscreteStates") ? fmi3OK : fmi3Error;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3EnterContinuousTimeMode", M(MODE_EVENT)))
        return fmi3Error;
    inst->mode = MODE_CONTINUOUS;
    return fmi3OK;
}

/* The model's bookkeeping of an accepted step (ClearanceWearJoint: wear and contact onsets). */
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean no_set_state_prior,
                                       fmi3Boolean *enter_event_mode, fmi3Boolean *terminate_simulation)
{
    Instance *inst = instance;
    (void)no_set_state_prior;
    if (inst == NULL || !mode_is(inst, "fmi3CompletedIntegratorStep", M(MODE_CONTINUOUS)))
        return fmi3Error;
    if (enter_event_mode == NULL || terminate_simulation == NULL) {
        LOG(inst, fmi3Error, "fmi3CompletedIntegratorStep: NULL output pointer");
        return fmi3Error;
    }
    *enter_event_mode = fmi3False;
    *terminate_simulation = fmi3False;
    return (fmi3Status)model_completed_integrator_step(inst->model, "fmi3CompletedIntegratorStep");
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3SetTime", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi3Error;
    return model_set_time(inst->model, time, "fmi3SetTime") ? fmi3OK : fmi3Error;
}

/* The model's N_CONTINUOUS_STATES continuous states: n must be that, the array given for n > 0. */
static int states_given(const Instance *inst, const char *function, size_t n, const void *x)
{
    if (inst == NULL)
        return 0;
    if (n != N_CONTINUOUS_STATES) {
        if (N_CONTINUOUS_STATES == 0)
            LOG(inst, fmi3Error, "%s: this FMU has no continuous states (%zu given)", function, n);
        else
            LOG(inst, fmi3Error, "%s: this FMU has %d continuous states (%zu given)", function, N_CONTINUOUS_STATES,
                n);
        return 0;
    }
    if (n > 0 && x == NULL) {
        LOG(inst, fmi3Error, "%s: NULL array", function);
        return 0;
    }
    return 1;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t nx)
{
    Instance *inst = instance;
    if (!states_given(inst, "fmi3SetContinuousStates", nx, x) ||
        !mode_is(inst, "fmi3SetContinuousStates", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi3Error;
    return model_set_continuous_states(inst->model, x, "fmi3SetContinuousStates") ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nx)
{
    Instance *inst = instance;
    if (!states_given(inst, "fmi3GetContinuousStateDerivatives", nx, derivatives) ||
        !mode_is(inst, "fmi3GetContinuousStateDerivatives", READABLE))
        return fmi3Error;
    return model_get_derivatives(inst->model, derivatives, "fmi3GetContinuousStateDerivatives") ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t nx)
{
    Instance *inst = instance;
    if (!states_given(inst, "fmi3GetContinuousStates", nx, x) || !mode_is(inst, "fmi3GetContinuousStates", READABLE))
        return fmi3Error;
    return model_get_continuous_states(inst->model, x, "fmi3GetContinuousStates") ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nx)
{
    Instance *inst = instance;
    if (!states_given(inst, "fmi3GetNominalsOfContinuousStates", nx, nominals))
        return fmi3Error;
    for (size_t i = 0; i < nx; i++)
        nominals[i] = 1.0;
    return fmi3OK;
}

/* The model's N_EVENT_INDICATORS event indicators. */
fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t ni)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3GetEventIndicators", READABLE))
        return fmi3Error;
    if (ni != N_EVENT_INDICATORS || (ni > 0 && indicators == NULL)) {
        LOG(inst, fmi3Error, "fmi3GetEventIndicators: this FMU has %d event indicator%s (%zu given)",
            N_EVENT_INDICATORS, N_EVENT_INDICATORS == 1 ? "" : "s", ni);
        return fmi3Error;
    }
    if (ni == 0)
        return fmi3OK;
    return model_get_event_indicators(inst->model, indicators, "fmi3GetEventIndicators") ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (n == NULL) {
        LOG(inst, fmi3Error, "fmi3GetNumberOfEventIndicators: NULL pointer");
        return fmi3Error;
    }
    *n = N_EVENT_INDICATORS;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (n == NULL) {
        LOG(inst, fmi3Error, "fmi3GetNumberOfContinuousStates: NULL pointer");
        return fmi3Error;
    }
    *n = N_CONTINUOUS_STATES;
    return fmi3OK;
}

/* ------------------------------------------------------------------ FMU state (fmu_state.c, as FMI 2.0's) */
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    return (fmi3Status)fmu_get_state(inst->model, state, (M(inst->mode) & INITIALISED) != 0, "fmi3GetFMUState");
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3SetFMUState", ~M(MODE_CONFIGURATION)))
        return fmi3Error;
    int initialised = -1;
    fmi3Status status = (fmi3Status)fmu_set_state(inst->model, state, &initialised, "fmi3SetFMUState");
    if (initialised == 1 && !(M(inst->mode) & (M(MODE_STEP) | M(MODE_EVENT) | M(MODE_CONTINUOUS))))
        inst->mode = inst->co_simulation ? MODE_STEP : MODE_EVENT;
    else if (initialised == 0 && (M(inst->mode) & INITIALISED))
        inst->mode = MODE_INITIALIZATION;
    return status;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    Instance *inst = instance;
    return inst == NULL ? fmi3Error : (fmi3Status)fmu_free_state(inst->model, state, "fmi3FreeFMUState");
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size)
{
    Instance *inst = instance;
    return inst == NULL ? fmi3Error
                        : (fmi3Status)fmu_serialized_state_size(inst->model, state, size, "fmi3SerializedFMUStateSize");
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[], size_t size)
{
    Instance *inst = instance;
    return inst == NULL ? fmi3Error
                        : (fmi3Status)fmu_serialize_state(inst->model, state, bytes, size, "fmi3SerializeFMUState");
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size, fmi3FMUState *state)
{
    Instance *inst = instance;
    return inst == NULL ? fmi3Error
                        : (fmi3Status)fmu_deserialize_state(inst->model, bytes, size, state, "fmi3DeserializeFMUState");
}
