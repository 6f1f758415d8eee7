/* FMI 3.0 layer of the native ClearanceWearJoint FMU: Co-Simulation and Model Exchange.
 *
 * The FMI 3.0 twin of fmi2Functions.c, on the same FMI-independent joint (joint_instance.c) and
 * the same kernels (model.h), with the same semantics (docs/model.md, "The FMU"):
 * - outputs are direct feed-through: the forces are evaluated from the current inputs at the
 *   first fmi3GetFloat64 of a joint output after an input changed;
 * - Co-Simulation: fmi3DoStep(t, h) accepts the step with the inputs held at t (wear, contact
 *   onsets); no event mode, no intermediate update, never returns early;
 * - Model Exchange: no continuous states; one event indicator, the signed penetration (a contact
 *   onset is a state event, where the approach velocity is stored: fmi3UpdateDiscreteStates);
 *   wear and the onset bookkeeping are applied at fmi3CompletedIntegratorStep over the step
 *   since the last completed one;
 * - parameters are fixed at fmi3ExitInitializationMode, where they are checked (fmi3Error with a
 *   message naming the variable and its allowed range); the three options are FMI 3
 *   enumerations, read and written with fmi3GetInt64 / fmi3SetInt64;
 * - the number of bushing points is the structural parameter n_points (UInt64): set it in
 *   Configuration Mode (fmi3EnterConfigurationMode .. fmi3ExitConfigurationMode, where the
 *   bushing is re-sized); the wear profile is the Float64 array wear_depth of n_points values;
 * - non-finite inputs: fmi3GetFloat64 of a joint output gives fmi3Error, fmi3DoStep fmi3Discard
 *   (state unchanged, the instance stays in Step Mode); finite inputs make it usable again;
 * - the FMU state is the FMI 2.0 layer's (the same bytes).
 * Value references (model_variables.h, generated): the scalars keep their FMI 2.0 ones, then
 * wear_depth and time.  FMI 3.0 has no memory callbacks: calloc/free.  Nothing is printed; every
 * message goes to the host's fmi3LogMessageCallback (none if it gave NULL).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "joint_instance.h"

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
    JointInstance *joint;
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;
    int co_simulation;             /* 1: Co-Simulation, 0: Model Exchange */
    Mode mode;
    uint64_t n_points;             /* Configuration Mode: the value set for n_points */
} Instance;

typedef struct {
    size_t size;
    unsigned char bytes[];
} FmuState;

/* ------------------------------------------------------------------ host callbacks */
/* FMI 3.0 has no memory callbacks: the C library's (JointAllocateFunction / JointReleaseFunction). */
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

/* ------------------------------------------------------------------ checks shared by the calls */
static int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    joint_log(inst->joint, fmi3Error, "%s: not allowed in state %s (FMI 3.0 call sequence)", function,
              MODE_NAMES[inst->mode]);
    return 0;
}

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr, const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        joint_log(inst->joint, fmi3Error, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

static void variable_name(fmi3ValueReference vr, char *out, size_t size)
{
    if (vr < FMI3_VR_FIRST_INPUT + N_INPUTS)
        snprintf(out, size, "%s", INPUT_NAMES[vr - FMI3_VR_FIRST_INPUT]);
    else if (vr >= FMI3_VR_FIRST_PARAMETER && vr < FMI3_VR_FIRST_PARAMETER + N_PARAMETERS)
        snprintf(out, size, "%s", PARAMETERS[vr - FMI3_VR_FIRST_PARAMETER].name);
    else if (vr == FMI3_VR_N_POINTS)
        snprintf(out, size, "n_points");
    else if (vr >= FMI3_VR_FIRST_OUTPUT && vr < FMI3_VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS)
        snprintf(out, size, "%s", OUTPUTS[vr - FMI3_VR_FIRST_OUTPUT].name);
    else if (vr == FMI3_VR_WEAR_DEPTH)
        snprintf(out, size, "wear_depth");
    else if (vr == FMI3_VR_TIME)
        snprintf(out, size, "time");
    else
        snprintf(out, size, "<no variable with valueReference %u>", (unsigned)vr);
}

/* A Float64 parameter (enumeration = 0) or an enumeration (enumeration = 1). */
static int is_parameter(fmi3ValueReference vr, int enumeration)
{
    return vr >= FMI3_VR_FIRST_PARAMETER && vr < FMI3_VR_FIRST_PARAMETER + N_PARAMETERS &&
           (PARAMETERS[vr - FMI3_VR_FIRST_PARAMETER].n_choices > 0) == enumeration;
}

static int is_scalar_output(fmi3ValueReference vr)
{
    return vr >= FMI3_VR_FIRST_OUTPUT && vr < FMI3_VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS;
}

/* The number of values nvr Float64 value references stand for (the array counts n_points);
 * 0 (logged) if one is not a Float64 variable. */
static int float64_values(const Instance *inst, const char *function, const fmi3ValueReference vr[], size_t nvr,
                          size_t n_values)
{
    size_t needed = 0;
    for (size_t i = 0; i < nvr; i++) {
        fmi3ValueReference r = vr[i];
        if (r == FMI3_VR_WEAR_DEPTH) {
            needed += (size_t)inst->joint->n_points;
        } else if (r < FMI3_VR_FIRST_INPUT + N_INPUTS || is_parameter(r, 0) || is_scalar_output(r) ||
                   r == FMI3_VR_TIME) {
            needed += 1;
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            joint_log(inst->joint, fmi3Error, "%s: %s is not a Float64 variable", function, name);
            return 0;
        }
    }
    if (needed != n_values) {
        joint_log(inst->joint, fmi3Error, "%s: nValues=%zu, but the %zu value references stand for %zu values "
                  "(wear_depth has n_points=%lld)", function, n_values, nvr, needed,
                  (long long)inst->joint->n_points);
        return 0;
    }
    return 1;
}

/* Scalars of one value each: nValues must equal nValueReferences. */
static int scalar_values(const Instance *inst, const char *function, size_t nvr, size_t n_values)
{
    if (nvr == n_values)
        return 1;
    joint_log(inst->joint, fmi3Error, "%s: nValues=%zu for %zu scalar variables", function, n_values, nvr);
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
    inst->joint->logging_on = logging_on;
    return fmi3OK;
}

static Instance *instantiate(const char *function, fmi3String instance_name, fmi3String token, fmi3Boolean logging_on,
                             fmi3InstanceEnvironment environment, fmi3LogMessageCallback log_message,
                             int co_simulation)
{
    const char *problem = NULL;
    if (instance_name == NULL || instance_name[0] == '\0')
        problem = "instanceName is missing";
    else if (token == NULL || strcmp(token, FMI3_INSTANTIATION_TOKEN) != 0)
        problem = "the instantiationToken does not match this FMU's modelDescription.xml ("
                  FMI3_INSTANTIATION_TOKEN ")";
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
    inst->n_points = FMI3_N_POINTS_START;
    inst->joint = joint_new(instance_name, FMI3_N_POINTS_START, logging_on, log_to_host, allocate, release, inst);
    if (inst->joint == NULL) {
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
    joint_free(inst->joint);
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
        joint_log(inst->joint, fmi3Error, "fmi3EnterInitializationMode: startTime=%g is invalid: allowed a finite time",
                  start_time);
        return fmi3Error;
    }
    inst->joint->time = inst->joint->last_accepted_time = start_time;
    inst->mode = MODE_INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3ExitInitializationMode", M(MODE_INITIALIZATION)))
        return fmi3Error;
    if (!joint_pack_parameters(inst->joint, "fmi3ExitInitializationMode"))
        return fmi3Error;
    inst->joint->last_accepted_time = inst->joint->time;
    inst->mode = inst->co_simulation ? MODE_STEP : MODE_EVENT;
    return fmi3OK;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (inst->co_simulation) {
        joint_log(inst->joint, fmi3Error, "fmi3EnterEventMode: this Co-Simulation FMU has no event mode "
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

/* Back to Instantiated with every variable at its start value, n_points too. */
fmi3Status fmi3Reset(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (!joint_resize(inst->joint, FMI3_N_POINTS_START))
        return fmi3Error;
    inst->n_points = FMI3_N_POINTS_START;
    inst->mode = MODE_INSTANTIATED;
    return fmi3OK;
}

/* ------------------------------------------------------------------ Configuration Mode: n_points */
fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3EnterConfigurationMode", M(MODE_INSTANTIATED)))
        return fmi3Error;
    inst->n_points = (uint64_t)inst->joint->n_points;
    inst->mode = MODE_CONFIGURATION;
    return fmi3OK;
}

/* Re-size the bushing to the n_points set; inputs, parameters and the time set before are kept. */
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3ExitConfigurationMode", M(MODE_CONFIGURATION)))
        return fmi3Error;
    JointInstance *joint = inst->joint;
    if ((int64_t)inst->n_points != joint->n_points) {
        double inputs[N_INPUTS], parameters[N_PARAMETERS];
        double time = joint->time;
        memcpy(inputs, joint->inputs, sizeof inputs);
        memcpy(parameters, joint->parameters, sizeof parameters);
        if (!joint_resize(joint, (int64_t)inst->n_points))
            return fmi3Error;   /* out of memory (logged): the old size stays, still in Configuration Mode */
        for (int i = 0; i < N_INPUTS; i++)
            joint_set_input(joint, i, inputs[i]);
        for (int i = 0; i < N_PARAMETERS; i++)
            joint_set_parameter(joint, i, parameters[i]);
        joint->time = joint->last_accepted_time = time;
    }
    inst->mode = MODE_INSTANTIATED;
    return fmi3OK;
}

/* ------------------------------------------------------------------ values */
fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 value[],
                          size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetFloat64", nvr, vr, value) || !mode_is(inst, "fmi3GetFloat64", READABLE) ||
        !float64_values(inst, "fmi3GetFloat64", vr, nvr, n_values))
        return fmi3Error;
    JointInstance *joint = inst->joint;
    size_t k = 0;
    for (size_t i = 0; i < nvr; i++) {
        fmi3ValueReference r = vr[i];
        if (r < FMI3_VR_FIRST_INPUT + N_INPUTS) {
            value[k++] = joint->inputs[r - FMI3_VR_FIRST_INPUT];
        } else if (is_parameter(r, 0)) {
            value[k++] = joint->parameters[r - FMI3_VR_FIRST_PARAMETER];
        } else if (is_scalar_output(r)) {
            const OutputInfo *o = &OUTPUTS[r - FMI3_VR_FIRST_OUTPUT];
            if (o->source == OUTPUT_FROM_RESULT) {
                if (!joint_evaluate(joint, "fmi3GetFloat64", o->name))
                    return fmi3Error;
                value[k++] = joint->result[o->index];
            } else {
                if (!joint_wear_summary(joint, "fmi3GetFloat64"))
                    return fmi3Error;
                value[k++] = o->source == OUTPUT_MAX_WEAR_DEPTH ? joint->max_wear_depth : joint->worn_volume;
            }
        } else if (r == FMI3_VR_WEAR_DEPTH) {
            memcpy(value + k, joint->wear_depth, (size_t)joint->n_points * sizeof(double));
            k += (size_t)joint->n_points;
        } else { /* FMI3_VR_TIME */
            value[k++] = joint->time;
        }
    }
    return fmi3OK;
}

/* A parameter may be set before fmi3ExitInitializationMode only. */
static int parameter_settable(const Instance *inst, const char *function, fmi3ValueReference vr)
{
    if (inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION)
        return 1;
    joint_log(inst->joint, fmi3Error, "%s: parameter %s is fixed: set it before fmi3ExitInitializationMode", function,
              PARAMETERS[vr - FMI3_VR_FIRST_PARAMETER].name);
    return 0;
}

static fmi3Status cannot_set(const Instance *inst, const char *function, fmi3ValueReference vr, const char *type)
{
    char name[96];
    variable_name(vr, name, sizeof name);
    joint_log(inst->joint, fmi3Error, "%s: %s is not a %s variable that can be set", function, name, type);
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
        fmi3ValueReference r = vr[i];
        if (r < FMI3_VR_FIRST_INPUT + N_INPUTS) {
            joint_set_input(inst->joint, (int)(r - FMI3_VR_FIRST_INPUT), value[i]);
        } else if (is_parameter(r, 0)) {
            if (!parameter_settable(inst, "fmi3SetFloat64", r))
                return fmi3Error;
            joint_set_parameter(inst->joint, (int)(r - FMI3_VR_FIRST_PARAMETER), value[i]);
        } else {
            return cannot_set(inst, "fmi3SetFloat64", r, "Float64");
        }
    }
    return fmi3OK;
}

/* The enumerations (rho_mode, wear_placement, sliding_distance): their item values. */
fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 value[],
                        size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetInt64", nvr, vr, value) || !mode_is(inst, "fmi3GetInt64", READABLE) ||
        !scalar_values(inst, "fmi3GetInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        if (!is_parameter(vr[i], 1)) {
            char name[96];
            variable_name(vr[i], name, sizeof name);
            joint_log(inst->joint, fmi3Error, "fmi3GetInt64: %s is not an Enumeration variable", name);
            return fmi3Error;
        }
        value[i] = (fmi3Int64)inst->joint->parameters[vr[i] - FMI3_VR_FIRST_PARAMETER];
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
        fmi3ValueReference r = vr[i];
        if (!is_parameter(r, 1))
            return cannot_set(inst, "fmi3SetInt64", r, "Enumeration");
        if (!parameter_settable(inst, "fmi3SetInt64", r))
            return fmi3Error;
        /* checked at fmi3ExitInitializationMode, like every parameter */
        joint_set_parameter(inst->joint, (int)(r - FMI3_VR_FIRST_PARAMETER), (double)value[i]);
    }
    return fmi3OK;
}

/* The structural parameter n_points: readable in every state, set in Configuration Mode. */
fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 value[],
                         size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetUInt64", nvr, vr, value) || !scalar_values(inst, "fmi3GetUInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] != FMI3_VR_N_POINTS) {
            char name[96];
            variable_name(vr[i], name, sizeof name);
            joint_log(inst->joint, fmi3Error, "fmi3GetUInt64: %s is not a UInt64 variable", name);
            return fmi3Error;
        }
        value[i] = inst->mode == MODE_CONFIGURATION ? inst->n_points : (fmi3UInt64)inst->joint->n_points;
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
        if (vr[i] != FMI3_VR_N_POINTS)
            return cannot_set(inst, "fmi3SetUInt64", vr[i], "UInt64");
        fmi3UInt64 n = value[i];
        if (inst->mode != MODE_CONFIGURATION) {
            if (n == (fmi3UInt64)inst->joint->n_points && (M(inst->mode) & SETTABLE))
                continue;   /* its current value: nothing changes */
            joint_log(inst->joint, fmi3Error,
                      "fmi3SetUInt64: the structural parameter n_points (now %lld) can be changed in Configuration "
                      "Mode only (fmi3EnterConfigurationMode after instantiation), not in state %s",
                      (long long)inst->joint->n_points, MODE_NAMES[inst->mode]);
            return fmi3Error;
        }
        if (n < FMI3_N_POINTS_MIN || n > FMI3_N_POINTS_MAX) {
            joint_log(inst->joint, fmi3Error,
                      "fmi3SetUInt64: structural parameter n_points=%llu is invalid: allowed an integer in [%d, %d]",
                      (unsigned long long)n, FMI3_N_POINTS_MIN, FMI3_N_POINTS_MAX);
            return fmi3Error;
        }
        inst->n_points = n;
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
        joint_log(inst->joint, fmi3Error, "%s: this FMU has no %s variables (valueReference %u)", #function,     \
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
        joint_log(inst->joint, fmi3Error, "%s: %s", #function, reason); \
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
NOT_PROVIDED(fmi3GetDirectionalDerivative,
             (fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,
              const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[], size_t n_seed,
              fmi3Float64 sensitivity[], size_t n_sensitivity),
             "providesDirectionalDerivatives is false for this FMU")
NOT_PROVIDED(fmi3GetAdjointDerivative,
             (fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,
              const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[], size_t n_seed,
              fmi3Float64 sensitivity[], size_t n_sensitivity),
             "providesAdjointDerivatives is false for this FMU")
NOT_PROVIDED(fmi3GetOutputDerivatives,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 orders[],
              fmi3Float64 values[], size_t n_values),
             "maxOutputDerivativeOrder is 0 for this FMU")

/* ------------------------------------------------------------------ Co-Simulation */
fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (!inst->co_simulation) {
        joint_log(inst->joint, fmi3Error, "fmi3EnterStepMode: a Co-Simulation function, this is Model Exchange");
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
        joint_log(inst->joint, fmi3Error, "fmi3DoStep: NULL output pointer");
        return fmi3Error;
    }
    JointInstance *joint = inst->joint;
    *event_handling_needed = fmi3False;
    *terminate_simulation = fmi3False;
    *early_return = fmi3False;
    *last_successful_time = joint->time;
    if (!isfinite(current_time)) {
        joint_log(joint, fmi3Error, "fmi3DoStep: currentCommunicationPoint=%g is not finite", current_time);
        return fmi3Discard;
    }
    double previous = joint->time;
    joint->time = current_time;
    int status = joint_accept_step(joint, step_size, "fmi3DoStep");
    if (status != JOINT_OK) {
        joint->time = previous;
        return (fmi3Status)status;
    }
    joint->time = joint->last_accepted_time = current_time + step_size;
    *last_successful_time = joint->time;
    return fmi3OK;
}

/* ------------------------------------------------------------------ Model Exchange */
/* A state event (a contact begins or ends): the contact-onset bookkeeping at the current inputs. */
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
        joint_log(inst->joint, fmi3Error, "fmi3UpdateDiscreteStates: NULL output pointer");
        return fmi3Error;
    }
    *discrete_states_need_update = fmi3False;
    *terminate_simulation = fmi3False;
    *nominals_changed = fmi3False;
    *values_changed = fmi3False;
    *next_event_time_defined = fmi3False;
    *next_event_time = 0.0;
    return joint_update_contact_memory(inst->joint, "fmi3UpdateDiscreteStates") ? fmi3OK : fmi3Error;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3EnterContinuousTimeMode", M(MODE_EVENT)))
        return fmi3Error;
    inst->mode = MODE_CONTINUOUS;
    return fmi3OK;
}

/* Wear and the onset bookkeeping over the step since the last completed one, at the current inputs. */
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean no_set_state_prior,
                                       fmi3Boolean *enter_event_mode, fmi3Boolean *terminate_simulation)
{
    Instance *inst = instance;
    (void)no_set_state_prior;
    if (inst == NULL || !mode_is(inst, "fmi3CompletedIntegratorStep", M(MODE_CONTINUOUS)))
        return fmi3Error;
    if (enter_event_mode == NULL || terminate_simulation == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3CompletedIntegratorStep: NULL output pointer");
        return fmi3Error;
    }
    *enter_event_mode = fmi3False;
    *terminate_simulation = fmi3False;
    return (fmi3Status)joint_completed_integrator_step(inst->joint, "fmi3CompletedIntegratorStep");
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3SetTime", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi3Error;
    return joint_set_time(inst->joint, time, "fmi3SetTime") ? fmi3OK : fmi3Error;
}

/* This FMU has no continuous states: n must be 0. */
static int no_states(const Instance *inst, const char *function, size_t n)
{
    if (inst == NULL)
        return 0;
    if (n == 0)
        return 1;
    joint_log(inst->joint, fmi3Error, "%s: this FMU has no continuous states (%zu given)", function, n);
    return 0;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t nx)
{
    (void)x;
    return no_states(instance, "fmi3SetContinuousStates", nx) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nx)
{
    (void)derivatives;
    return no_states(instance, "fmi3GetContinuousStateDerivatives", nx) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t nx)
{
    (void)x;
    return no_states(instance, "fmi3GetContinuousStates", nx) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nx)
{
    (void)nominals;
    return no_states(instance, "fmi3GetNominalsOfContinuousStates", nx) ? fmi3OK : fmi3Error;
}

/* The event indicator: the signed penetration of the deepest bushing point at the current inputs. */
fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t ni)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3GetEventIndicators", READABLE))
        return fmi3Error;
    if (ni != N_EVENT_INDICATORS || indicators == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3GetEventIndicators: this FMU has %d event indicator (%zu given)",
                  N_EVENT_INDICATORS, ni);
        return fmi3Error;
    }
    return joint_event_indicator(inst->joint, "fmi3GetEventIndicators", &indicators[0]) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (n == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3GetNumberOfEventIndicators: NULL pointer");
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
        joint_log(inst->joint, fmi3Error, "fmi3GetNumberOfContinuousStates: NULL pointer");
        return fmi3Error;
    }
    *n = 0;
    return fmi3OK;
}

/* ------------------------------------------------------------------ FMU state (the FMI 2.0 layer's bytes) */
static FmuState *new_state(const Instance *inst)
{
    size_t size = joint_state_size(inst->joint);
    FmuState *s = calloc(1, sizeof *s + size);
    if (s == NULL)
        joint_log(inst->joint, fmi3Error, "FMU state: out of memory");
    else
        s->size = size;
    return s;
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (state == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3GetFMUState: NULL state pointer");
        return fmi3Error;
    }
    FmuState *s = *state;
    if (s == NULL) {
        if ((s = new_state(inst)) == NULL)
            return fmi3Error;
        *state = s;
    } else if (s->size != joint_state_size(inst->joint)) {
        joint_log(inst->joint, fmi3Error, "fmi3GetFMUState: the state given to overwrite is not of this FMU");
        return fmi3Error;
    }
    joint_write_state(inst->joint, s->bytes, (M(inst->mode) & INITIALISED) != 0);
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state)
{
    Instance *inst = instance;
    if (inst == NULL || !mode_is(inst, "fmi3SetFMUState", ~M(MODE_CONFIGURATION)))
        return fmi3Error;
    const FmuState *s = state;
    if (s == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3SetFMUState: NULL state");
        return fmi3Error;
    }
    if (s->size != joint_state_size(inst->joint)) {
        joint_log(inst->joint, fmi3Error, "fmi3SetFMUState: a state of %zu bytes, this instance's (n_points=%lld) "
                  "have %zu", s->size, (long long)inst->joint->n_points, joint_state_size(inst->joint));
        return fmi3Error;
    }
    int initialised = 0;
    int ok = joint_read_state(inst->joint, s->bytes, &initialised, "fmi3SetFMUState");
    if (initialised && !(M(inst->mode) & (M(MODE_STEP) | M(MODE_EVENT) | M(MODE_CONTINUOUS))))
        inst->mode = inst->co_simulation ? MODE_STEP : MODE_EVENT;
    else if (!initialised && (M(inst->mode) & INITIALISED))
        inst->mode = MODE_INITIALIZATION;
    return ok ? fmi3OK : fmi3Error;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (state == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3FreeFMUState: NULL state pointer");
        return fmi3Error;
    }
    free(*state);
    *state = NULL;
    return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    const FmuState *s = state;
    if (s == NULL || size == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3SerializedFMUStateSize: NULL state or size pointer");
        return fmi3Error;
    }
    *size = s->size;
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[], size_t size)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    const FmuState *s = state;
    if (s == NULL || bytes == NULL || size < s->size) {
        joint_log(inst->joint, fmi3Error,
                  "fmi3SerializeFMUState: NULL state or buffer, or a buffer of %zu bytes for a state of %zu", size,
                  s != NULL ? s->size : (size_t)0);
        return fmi3Error;
    }
    memcpy(bytes, s->bytes, s->size);
    return fmi3OK;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size, fmi3FMUState *state)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (bytes == NULL || state == NULL) {
        joint_log(inst->joint, fmi3Error, "fmi3DeserializeFMUState: NULL bytes or state pointer");
        return fmi3Error;
    }
    if (!joint_state_valid(inst->joint, bytes, size, "fmi3DeserializeFMUState"))
        return fmi3Error;
    FmuState *s = *state;
    if (s != NULL && s->size != size) {
        joint_log(inst->joint, fmi3Error, "fmi3DeserializeFMUState: the state given to overwrite is not of this FMU");
        return fmi3Error;
    }
    if (s == NULL && (s = new_state(inst)) == NULL)
        return fmi3Error;
    memcpy(s->bytes, bytes, size);
    *state = s;
    return fmi3OK;
}
