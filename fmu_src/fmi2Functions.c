/* FMI 2.0 layer of the native FMUs: Co-Simulation and Model Exchange, for every model.
 *
 * Shaped like the Modelica Reference-FMUs' fmi2Functions.c: this file owns the FMI 2.0 call
 * sequence, and calls the model through the interface of fmu_model.h
 * (joint_model.c: ClearanceWearJoint; slider_crank_model.c: SliderCrank), whose physics is its
 * numba kernels compiled ahead of time.  Each model's variable table is generated into
 * model_variables.h by wearjoint/fmu/build_native.py.
 *
 * - parameters are fixed at exitInitializationMode, where the model checks them (fmi2Error with
 *   a message naming the variable and its allowed range);
 * - a value the model cannot compute (e.g. from non-finite inputs) gives fmi2Error, a step it
 *   cannot take fmi2Discard (state unchanged);
 * - FMU states (fmu_state.c): in memory the model's values copied as they are; serialised the state
 *   format (checksum), every check on deserialisation.
 * Nothing is printed; every message goes to the host's logger.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmu_model.h"
#include "model_variables.h"

typedef enum {
    MODE_INSTANTIATED, MODE_INITIALIZATION, MODE_STEP_COMPLETE, MODE_EVENT, MODE_CONTINUOUS, MODE_TERMINATED
} Mode;
static const char *const MODE_NAMES[] = {"instantiated", "initialization mode", "step complete", "event mode",
                                         "continuous-time mode", "terminated"};
#define M(mode) (1u << (mode))
#define INITIALISED (M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | M(MODE_CONTINUOUS) | M(MODE_TERMINATED))

typedef struct {
    FmuModel *model;
    fmi2CallbackFunctions callbacks;
    fmi2Type type;
    Mode mode;
} Instance;

/* ------------------------------------------------------------------ host callbacks */
/* The host's memory functions (FMI 2.0 callbacks; calloc/free if it gives none). */
static void *allocate(void *environment, size_t n, size_t size)
{
    const fmi2CallbackFunctions *callbacks = environment;
    return callbacks->allocateMemory != NULL ? callbacks->allocateMemory(n, size) : calloc(n, size);
}

static void release(void *environment, void *p)
{
    const fmi2CallbackFunctions *callbacks = environment;
    if (p == NULL)
        return;
    if (callbacks->freeMemory != NULL)
        callbacks->freeMemory(p);
    else
        free(p);
}

/* The complete message as the logger's format, '%' doubled: hosts that do not format (a
 * ctypes callback cannot read variadic arguments) show it as it is. */
static void log_to_host(void *environment, const char *name, int status, const char *category, const char *message)
{
    const fmi2CallbackFunctions *callbacks = environment;
    char escaped[2048];
    size_t n = 0;
    for (const char *c = message; *c != '\0' && n + 2 < sizeof escaped; c++) {
        if (*c == '%')
            escaped[n++] = '%';
        escaped[n++] = *c;
    }
    escaped[n] = '\0';
    callbacks->logger(callbacks->componentEnvironment, name, (fmi2Status)status, category, escaped);
}

#define LOG(inst, ...) fmu_log(model_host((inst)->model), __VA_ARGS__)

/* ------------------------------------------------------------------ checks shared by the calls */
static int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    LOG(inst, fmi2Error, "%s: not allowed in state %s (FMI 2.0 call sequence)", function,
              MODE_NAMES[inst->mode]);
    return 0;
}

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr, const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        LOG(inst, fmi2Error, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

static void not_a_variable(const Instance *inst, const char *function, fmi2ValueReference vr, const char *what)
{
    char name[96];
    model_variable_name(inst->model, 2, vr, name, sizeof name);
    LOG(inst, fmi2Error, "%s: %s%s", function, name, what);
}

/* ------------------------------------------------------------------ lifetime */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instance_name, fmi2Type fmu_type, fmi2String guid,
                              fmi2String resource_location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging_on)
{
    (void)resource_location;
    (void)visible;
    if (functions == NULL || functions->logger == NULL)
        return NULL; /* nowhere to report anything: the logger is mandatory in FMI 2.0 */
    const char *name = instance_name != NULL ? instance_name : "";
    const char *problem = NULL;
    if (instance_name == NULL || instance_name[0] == '\0')
        problem = "fmi2Instantiate: instanceName is missing";
    else if (fmu_type != fmi2CoSimulation && fmu_type != fmi2ModelExchange)
        problem = "fmi2Instantiate: fmuType must be fmi2ModelExchange or fmi2CoSimulation";
    else if (guid == NULL || strcmp(guid, MODEL_GUID) != 0)
        problem = "fmi2Instantiate: the GUID does not match this FMU's modelDescription.xml (" MODEL_GUID ")";
    if (problem != NULL) {
        functions->logger(functions->componentEnvironment, name, fmi2Error, "logStatusError", "%s", problem);
        return NULL;
    }
    Instance *inst = allocate((void *)functions, 1, sizeof *inst);
    if (inst == NULL) {
        functions->logger(functions->componentEnvironment, name, fmi2Error, "logStatusError", "%s",
                          "fmi2Instantiate: out of memory");
        return NULL;
    }
    inst->callbacks = *functions;
    inst->type = fmu_type;
    inst->mode = MODE_INSTANTIATED;
    inst->model = model_new(name, logging_on, log_to_host, allocate, release, &inst->callbacks);
    if (inst->model == NULL) {
        release((void *)functions, inst);
        return NULL;
    }
    return inst;
}

void fmi2FreeInstance(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return;
    fmi2CallbackFunctions callbacks = inst->callbacks;
    model_free(inst->model);
    release(&callbacks, inst);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean logging_on, size_t n_categories,
                               const fmi2String categories[])
{
    Instance *inst = c;
    (void)categories;
    (void)n_categories;
    if (inst == NULL)
        return fmi2Error;
    model_host(inst->model)->logging_on = logging_on;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance,
                               fmi2Real start_time, fmi2Boolean stop_time_defined, fmi2Real stop_time)
{
    Instance *inst = c;
    (void)tolerance_defined;
    (void)tolerance;
    (void)stop_time_defined;
    (void)stop_time;
    if (inst == NULL || !mode_is(inst, "fmi2SetupExperiment", M(MODE_INSTANTIATED)))
        return fmi2Error;
    if (!isfinite(start_time)) {
        LOG(inst, fmi2Error, "fmi2SetupExperiment: startTime=%g is invalid: allowed a finite time",
                  start_time);
        return fmi2Error;
    }
    model_set_start_time(inst->model, start_time);
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2EnterInitializationMode", M(MODE_INSTANTIATED)))
        return fmi2Error;
    inst->mode = MODE_INITIALIZATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2ExitInitializationMode", M(MODE_INITIALIZATION)))
        return fmi2Error;
    if (!model_exit_initialization(inst->model, "fmi2ExitInitializationMode"))
        return fmi2Error;
    inst->mode = inst->type == fmi2CoSimulation ? MODE_STEP_COMPLETE : MODE_EVENT;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2Terminate", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    inst->mode = MODE_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (!model_reset(inst->model))
        return fmi2Error;
    inst->mode = MODE_INSTANTIATED;
    return fmi2OK;
}

/* ------------------------------------------------------------------ values */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetReal", nvr, vr, value) ||
        !mode_is(inst, "fmi2GetReal", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {   /* FMI 2.0 has no arrays: every Real the model gets is one value */
        int done = model_get_float64(inst->model, 2, vr[i], &value[i], "fmi2GetReal");
        if (done == -1)
            not_a_variable(inst, "fmi2GetReal", vr[i], " is not a Real variable");
        if (done != 1)
            return fmi2Error;
    }
    return fmi2OK;
}

/* A parameter may be set before exitInitializationMode only. */
static int parameters_settable(const Instance *inst)
{
    return inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION;
}

/* After a set: -1 the variable cannot be set, -2 a parameter after initialisation (logged here). */
static fmi2Status set_failed(const Instance *inst, const char *function, fmi2ValueReference vr, int done)
{
    char name[96];
    model_variable_name(inst->model, 2, vr, name, sizeof name);
    if (done == -1)
        LOG(inst, fmi2Error, "%s: variable %s cannot be set", function, name);
    else if (done == -2)
        LOG(inst, fmi2Error, "%s: parameter %s is fixed: set it before fmi2ExitInitializationMode", function, name);
    return fmi2Error;
}

#define SETTABLE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | \
                  M(MODE_CONTINUOUS))

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetReal", nvr, vr, value) || !mode_is(inst, "fmi2SetReal", SETTABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_float64(inst->model, 2, vr[i], value[i], parameters_settable(inst), "fmi2SetReal");
        if (done != 1)
            return set_failed(inst, "fmi2SetReal", vr[i], done);
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetInteger", nvr, vr, value) ||
        !mode_is(inst, "fmi2GetInteger", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int64_t v = 0;
        int done = model_get_integer(inst->model, 2, vr[i], &v, "fmi2GetInteger");
        if (done == -1)
            not_a_variable(inst, "fmi2GetInteger", vr[i], " is not an Integer variable");
        if (done != 1)
            return fmi2Error;
        value[i] = (fmi2Integer)v;
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetInteger", nvr, vr, value) || !mode_is(inst, "fmi2SetInteger", SETTABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_integer(inst->model, 2, vr[i], value[i], parameters_settable(inst), "fmi2SetInteger");
        if (done != 1)
            return set_failed(inst, "fmi2SetInteger", vr[i], done);
    }
    return fmi2OK;
}

#define NO_VARIABLES_OF_TYPE(function, type, qualifier)                                                       \
    fmi2Status function(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, qualifier type value[])    \
    {                                                                                                         \
        Instance *inst = c;                                                                                   \
        if (!arrays_given(inst, #function, nvr, vr, value))                                                   \
            return fmi2Error;                                                                                 \
        if (nvr == 0)                                                                                         \
            return fmi2OK;                                                                                    \
        LOG(inst, fmi2Error, "%s: this FMU has no %s variables (valueReference %u)", #function,  \
                  #type, (unsigned)vr[0]);                                                                    \
        return fmi2Error;                                                                                     \
    }

NO_VARIABLES_OF_TYPE(fmi2GetBoolean, fmi2Boolean, )
NO_VARIABLES_OF_TYPE(fmi2SetBoolean, fmi2Boolean, const)
NO_VARIABLES_OF_TYPE(fmi2GetString, fmi2String, )
NO_VARIABLES_OF_TYPE(fmi2SetString, fmi2String, const)

/* ------------------------------------------------------------------ Co-Simulation */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real current_time, fmi2Real step_size, fmi2Boolean no_set_state_before)
{
    Instance *inst = c;
    (void)no_set_state_before;
    if (inst == NULL || !mode_is(inst, "fmi2DoStep", M(MODE_STEP_COMPLETE)))
        return fmi2Error;
    if (!isfinite(current_time)) {
        LOG(inst, fmi2Error, "fmi2DoStep: currentCommunicationPoint=%g is not finite", current_time);
        return fmi2Discard;
    }
    return (fmi2Status)model_do_step(inst->model, current_time, step_size, "fmi2DoStep");
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    LOG(inst, fmi2Error, "fmi2CancelStep: doStep always completes synchronously here");
    return fmi2Error;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value)
{
    Instance *inst = c;
    if (inst == NULL || value == NULL)
        return fmi2Error;
    if (kind != fmi2LastSuccessfulTime) {
        LOG(inst, fmi2Error, "fmi2GetRealStatus: only fmi2LastSuccessfulTime is available");
        return fmi2Error;
    }
    *value = model_time(inst->model);
    return fmi2OK;
}

#define NO_STATUS_OF_TYPE(function, type)                                                            \
    fmi2Status function(fmi2Component c, const fmi2StatusKind kind, type *value)                    \
    {                                                                                                \
        Instance *inst = c;                                                                          \
        (void)kind;                                                                                  \
        (void)value;                                                                                 \
        if (inst == NULL)                                                                            \
            return fmi2Error;                                                                        \
        LOG(inst, fmi2Error, "%s: doStep never returns fmi2Pending here", #function);   \
        return fmi2Error;                                                                            \
    }

NO_STATUS_OF_TYPE(fmi2GetStatus, fmi2Status)
NO_STATUS_OF_TYPE(fmi2GetIntegerStatus, fmi2Integer)
NO_STATUS_OF_TYPE(fmi2GetBooleanStatus, fmi2Boolean)
NO_STATUS_OF_TYPE(fmi2GetStringStatus, fmi2String)

/* (the unused parameters of these functions are named, for the reader; -Wno-unused-parameter) */
#define NOT_PROVIDED(function, parameters, reason)                \
    fmi2Status function parameters                                \
    {                                                             \
        Instance *inst = c;                                       \
        if (inst == NULL)                                         \
            return fmi2Error;                                     \
        LOG(inst, fmi2Error, "%s: %s", #function, reason); \
        return fmi2Error;                                         \
    }

NOT_PROVIDED(fmi2SetRealInputDerivatives,
             (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer order[],
              const fmi2Real value[]),
             "canInterpolateInputs is false for this FMU")
NOT_PROVIDED(fmi2GetRealOutputDerivatives,
             (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer order[],
              fmi2Real value[]),
             "maxOutputDerivativeOrder is 0 for this FMU")

/* dv_unknown = J dv_known, J the partial derivatives of the unknowns (outputs) with respect to the knowns (inputs). */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[], size_t n_unknown,
                                        const fmi2ValueReference known[], size_t n_known, const fmi2Real dv_known[],
                                        fmi2Real dv_unknown[])
{
    Instance *inst = c;
    const char *function = "fmi2GetDirectionalDerivative";
    if (!arrays_given(inst, function, n_unknown, unknown, dv_unknown) ||
        !arrays_given(inst, function, n_known, known, dv_known) ||
        !mode_is(inst, function, M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    int done = model_directional_derivative(inst->model, 2, unknown, n_unknown, known, n_known, dv_known, dv_unknown,
                                            function);
    if (done == -1)
        LOG(inst, fmi2Error, "%s: providesDirectionalDerivative is false for this FMU", function);
    return done == 1 ? fmi2OK : fmi2Error;
}

/* ------------------------------------------------------------------ Model Exchange */
fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2EnterEventMode", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi2Error;
    inst->mode = MODE_EVENT;
    return fmi2OK;
}

/* An event: the model's update (ClearanceWearJoint: the contact-onset bookkeeping). */
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2NewDiscreteStates", M(MODE_EVENT)))
        return fmi2Error;
    if (info == NULL) {
        LOG(inst, fmi2Error, "fmi2NewDiscreteStates: NULL eventInfo");
        return fmi2Error;
    }
    memset(info, 0, sizeof *info);
    return model_event_update(inst->model, "fmi2NewDiscreteStates") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2EnterContinuousTimeMode", M(MODE_EVENT)))
        return fmi2Error;
    inst->mode = MODE_CONTINUOUS;
    return fmi2OK;
}

/* The model's bookkeeping of an accepted step (ClearanceWearJoint: wear and contact onsets). */
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set_state_prior, fmi2Boolean *enter_event_mode,
                                       fmi2Boolean *terminate_simulation)
{
    Instance *inst = c;
    (void)no_set_state_prior;
    if (inst == NULL || !mode_is(inst, "fmi2CompletedIntegratorStep", M(MODE_CONTINUOUS)))
        return fmi2Error;
    if (enter_event_mode == NULL || terminate_simulation == NULL) {
        LOG(inst, fmi2Error, "fmi2CompletedIntegratorStep: NULL output pointer");
        return fmi2Error;
    }
    *enter_event_mode = fmi2False;
    *terminate_simulation = fmi2False;
    return (fmi2Status)model_completed_integrator_step(inst->model, "fmi2CompletedIntegratorStep");
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2SetTime", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi2Error;
    return model_set_time(inst->model, time, "fmi2SetTime") ? fmi2OK : fmi2Error;
}

/* The model's N_CONTINUOUS_STATES continuous states: nx must be that, x given for nx > 0. */
static int states_given(const Instance *inst, const char *function, size_t nx, const void *x)
{
    if (inst == NULL)
        return 0;
    if (nx != N_CONTINUOUS_STATES) {
        if (N_CONTINUOUS_STATES == 0)
            LOG(inst, fmi2Error, "%s: this FMU has no continuous states (nx=%zu given)", function, nx);
        else
            LOG(inst, fmi2Error, "%s: this FMU has %d continuous states (nx=%zu given)", function,
                N_CONTINUOUS_STATES, nx);
        return 0;
    }
    if (nx > 0 && x == NULL) {
        LOG(inst, fmi2Error, "%s: NULL array", function);
        return 0;
    }
    return 1;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    Instance *inst = c;
    if (!states_given(inst, "fmi2SetContinuousStates", nx, x) ||
        !mode_is(inst, "fmi2SetContinuousStates", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi2Error;
    return model_set_continuous_states(inst->model, x, "fmi2SetContinuousStates") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    Instance *inst = c;
    if (!states_given(inst, "fmi2GetDerivatives", nx, derivatives) ||
        !mode_is(inst, "fmi2GetDerivatives", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    return model_get_derivatives(inst->model, derivatives, "fmi2GetDerivatives") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    Instance *inst = c;
    if (!states_given(inst, "fmi2GetContinuousStates", nx, x) ||
        !mode_is(inst, "fmi2GetContinuousStates", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    return model_get_continuous_states(inst->model, x, "fmi2GetContinuousStates") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    Instance *inst = c;
    if (!states_given(inst, "fmi2GetNominalsOfContinuousStates", nx, x_nominal))
        return fmi2Error;
    for (size_t i = 0; i < nx; i++)
        x_nominal[i] = 1.0;
    return fmi2OK;
}

/* The model's N_EVENT_INDICATORS event indicators. */
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real indicators[], size_t ni)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2GetEventIndicators", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    if (ni != N_EVENT_INDICATORS || (ni > 0 && indicators == NULL)) {
        LOG(inst, fmi2Error, "fmi2GetEventIndicators: this FMU has %d event indicator%s (ni=%zu given)",
            N_EVENT_INDICATORS, N_EVENT_INDICATORS == 1 ? "" : "s", ni);
        return fmi2Error;
    }
    if (ni == 0)
        return fmi2OK;
    return model_get_event_indicators(inst->model, indicators, "fmi2GetEventIndicators") ? fmi2OK : fmi2Error;
}

/* ------------------------------------------------------------------ FMU state (fmu_state.c) */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    return (fmi2Status)fmu_get_state(inst->model, state, (M(inst->mode) & INITIALISED) != 0, "fmi2GetFMUstate");
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    int initialised = -1;
    fmi2Status status = (fmi2Status)fmu_set_state(inst->model, state, &initialised, "fmi2SetFMUstate");
    if (initialised == 1 && !(M(inst->mode) & (M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | M(MODE_CONTINUOUS))))
        inst->mode = inst->type == fmi2CoSimulation ? MODE_STEP_COMPLETE : MODE_EVENT;
    else if (initialised == 0 && (M(inst->mode) & INITIALISED))
        inst->mode = MODE_INITIALIZATION;
    return status;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    Instance *inst = c;
    return inst == NULL ? fmi2Error : (fmi2Status)fmu_free_state(inst->model, state, "fmi2FreeFMUstate");
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size)
{
    Instance *inst = c;
    return inst == NULL ? fmi2Error
                        : (fmi2Status)fmu_serialized_state_size(inst->model, state, size, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size)
{
    Instance *inst = c;
    return inst == NULL ? fmi2Error
                        : (fmi2Status)fmu_serialize_state(inst->model, state, (unsigned char *)bytes, size,
                                                          "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state)
{
    Instance *inst = c;
    return inst == NULL ? fmi2Error
                        : (fmi2Status)fmu_deserialize_state(inst->model, (const unsigned char *)bytes, size, state,
                                                            "fmi2DeSerializeFMUstate");
}
