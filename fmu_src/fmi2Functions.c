/* FMI 2.0 layer of the native ClearanceWearJoint FMU: Co-Simulation and Model Exchange.
 *
 * Shaped like the Modelica Reference-FMUs' fmi2Functions.c: this file owns the FMI 2.0 call
 * sequence, the value references and the FMU-state objects; the joint (memory, parameters,
 * kernels, state bytes) is joint_instance.c, and the physics is the joint's numba kernels
 * compiled ahead of time (model.h).  The variable table is generated from
 * wearjoint/fmu/variables.py into model_variables.h by wearjoint/fmu/build_native.py.
 *
 * Semantics (docs/model.md, "The FMU"), the same as the pythonfmu backend's:
 * - outputs are direct feed-through: the forces are evaluated from the current inputs at
 *   the first getReal of a joint output after an input changed;
 * - Co-Simulation: doStep(t, h) accepts the step with the inputs held at t (wear, contact
 *   onsets);
 * - Model Exchange: no continuous states; one event indicator, the signed penetration of the
 *   deepest point (a contact onset is a state event, where the approach velocity is stored:
 *   fmi2NewDiscreteStates); wear and the onset bookkeeping are applied at
 *   fmi2CompletedIntegratorStep over the step since the last completed one;
 * - parameters are fixed at exitInitializationMode, where they are checked (fmi2Error with a
 *   message naming the variable and its allowed range);
 * - non-finite inputs: getReal of a joint output gives fmi2Error, doStep fmi2Discard (state
 *   unchanged); finite inputs set afterwards make the instance usable again;
 * - the FMU state is its serialised form (the pythonfmu backend's layout).
 * Nothing is printed; every message goes to the host's logger.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "joint_instance.h"

typedef enum {
    MODE_INSTANTIATED, MODE_INITIALIZATION, MODE_STEP_COMPLETE, MODE_EVENT, MODE_CONTINUOUS, MODE_TERMINATED
} Mode;
static const char *const MODE_NAMES[] = {"instantiated", "initialization mode", "step complete", "event mode",
                                         "continuous-time mode", "terminated"};
#define M(mode) (1u << (mode))
#define INITIALISED (M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | M(MODE_CONTINUOUS) | M(MODE_TERMINATED))

typedef struct {
    JointInstance *joint;
    fmi2CallbackFunctions callbacks;
    fmi2Type type;
    Mode mode;
} Instance;

typedef struct {
    size_t size;
    unsigned char bytes[];
} FmuState;

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

/* ------------------------------------------------------------------ checks shared by the calls */
static int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    joint_log(inst->joint, fmi2Error, "%s: not allowed in state %s (FMI 2.0 call sequence)", function,
              MODE_NAMES[inst->mode]);
    return 0;
}

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr, const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        joint_log(inst->joint, fmi2Error, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

static void variable_name(fmi2ValueReference vr, char *out, size_t size)
{
    if (vr < N_INPUTS)
        snprintf(out, size, "%s", INPUT_NAMES[vr]);
    else if (vr < VR_FIRST_PARAMETER + N_PARAMETERS)
        snprintf(out, size, "%s", PARAMETERS[vr - VR_FIRST_PARAMETER].name);
    else if (vr == VR_N_POINTS)
        snprintf(out, size, "n_points");
    else if (vr < VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS)
        snprintf(out, size, "%s", OUTPUTS[vr - VR_FIRST_OUTPUT].name);
    else if (vr < VR_FIRST_WEAR_DEPTH + N_POINTS)
        snprintf(out, size, "wear_depth[%u]", (unsigned)(vr - VR_FIRST_WEAR_DEPTH + 1));
    else
        snprintf(out, size, "<no variable with valueReference %u>", (unsigned)vr);
}

static int is_parameter(fmi2ValueReference vr, int choice)
{
    return vr >= VR_FIRST_PARAMETER && vr < VR_FIRST_PARAMETER + N_PARAMETERS &&
           (PARAMETERS[vr - VR_FIRST_PARAMETER].n_choices > 0) == choice;
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
    inst->joint = joint_new(name, N_POINTS, logging_on, log_to_host, allocate, release, &inst->callbacks);
    if (inst->joint == NULL) {
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
    joint_free(inst->joint);
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
    inst->joint->logging_on = logging_on;
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
        joint_log(inst->joint, fmi2Error, "fmi2SetupExperiment: startTime=%g is invalid: allowed a finite time",
                  start_time);
        return fmi2Error;
    }
    inst->joint->time = inst->joint->last_accepted_time = start_time;
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
    if (!joint_pack_parameters(inst->joint, "fmi2ExitInitializationMode"))
        return fmi2Error;
    inst->joint->last_accepted_time = inst->joint->time;
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
    joint_reset(inst->joint);
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
    JointInstance *joint = inst->joint;
    int evaluated = 0; /* the forces are current after the first joint output: no check per output */
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r < N_INPUTS) {
            value[i] = joint->inputs[r];
        } else if (is_parameter(r, 0)) {
            value[i] = joint->parameters[r - VR_FIRST_PARAMETER];
        } else if (r >= VR_FIRST_OUTPUT && r < VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS) {
            const OutputInfo *o = &OUTPUTS[r - VR_FIRST_OUTPUT];
            if (o->source == OUTPUT_FROM_RESULT) {
                if (!evaluated && !joint_evaluate(joint, "fmi2GetReal", o->name))
                    return fmi2Error;
                evaluated = 1;
                value[i] = joint->result[o->index];
            } else {
                if (!joint_wear_summary(joint, "fmi2GetReal"))
                    return fmi2Error;
                value[i] = o->source == OUTPUT_MAX_WEAR_DEPTH ? joint->max_wear_depth : joint->worn_volume;
            }
        } else if (r >= VR_FIRST_WEAR_DEPTH && r < VR_FIRST_WEAR_DEPTH + N_POINTS) {
            value[i] = joint->wear_depth[r - VR_FIRST_WEAR_DEPTH];
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            joint_log(joint, fmi2Error, "fmi2GetReal: %s is not a Real variable", name);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

/* A parameter may be set before exitInitializationMode only. */
static int parameter_settable(const Instance *inst, const char *function, fmi2ValueReference vr)
{
    if (inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION)
        return 1;
    joint_log(inst->joint, fmi2Error, "%s: parameter %s is fixed: set it before fmi2ExitInitializationMode", function,
              PARAMETERS[vr - VR_FIRST_PARAMETER].name);
    return 0;
}

#define SETTABLE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | \
                  M(MODE_CONTINUOUS))

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetReal", nvr, vr, value) || !mode_is(inst, "fmi2SetReal", SETTABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r < N_INPUTS) {
            joint_set_input(inst->joint, (int)r, value[i]);
        } else if (is_parameter(r, 0)) {
            if (!parameter_settable(inst, "fmi2SetReal", r))
                return fmi2Error;
            joint_set_parameter(inst->joint, (int)(r - VR_FIRST_PARAMETER), value[i]);
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            joint_log(inst->joint, fmi2Error, "fmi2SetReal: variable %s cannot be set", name);
            return fmi2Error;
        }
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
        fmi2ValueReference r = vr[i];
        if (r == VR_N_POINTS) {
            value[i] = (fmi2Integer)inst->joint->n_points;
        } else if (is_parameter(r, 1)) {
            value[i] = (fmi2Integer)inst->joint->parameters[r - VR_FIRST_PARAMETER];
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            joint_log(inst->joint, fmi2Error, "fmi2GetInteger: %s is not an Integer variable", name);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetInteger", nvr, vr, value) || !mode_is(inst, "fmi2SetInteger", SETTABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r == VR_N_POINTS) {
            if (value[i] != inst->joint->n_points) {
                joint_log(inst->joint, fmi2Error,
                          "fmi2SetInteger: n_points is fixed at %lld when the FMU is built; rebuild it for %d "
                          "points (wearjoint build-fmu --n-points %d)",
                          (long long)inst->joint->n_points, (int)value[i], (int)value[i]);
                return fmi2Error;
            }
        } else if (is_parameter(r, 1)) {
            if (!parameter_settable(inst, "fmi2SetInteger", r))
                return fmi2Error;
            joint_set_parameter(inst->joint, (int)(r - VR_FIRST_PARAMETER), value[i]);
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            joint_log(inst->joint, fmi2Error, "fmi2SetInteger: variable %s cannot be set", name);
            return fmi2Error;
        }
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
        joint_log(inst->joint, fmi2Error, "%s: this FMU has no %s variables (valueReference %u)", #function,  \
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
        joint_log(inst->joint, fmi2Error, "fmi2DoStep: currentCommunicationPoint=%g is not finite", current_time);
        return fmi2Discard;
    }
    inst->joint->time = current_time;
    int status = joint_accept_step(inst->joint, step_size, "fmi2DoStep");
    if (status != JOINT_OK)
        return (fmi2Status)status;
    inst->joint->time = inst->joint->last_accepted_time = current_time + step_size;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    joint_log(inst->joint, fmi2Error, "fmi2CancelStep: doStep always completes synchronously here");
    return fmi2Error;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value)
{
    Instance *inst = c;
    if (inst == NULL || value == NULL)
        return fmi2Error;
    if (kind != fmi2LastSuccessfulTime) {
        joint_log(inst->joint, fmi2Error, "fmi2GetRealStatus: only fmi2LastSuccessfulTime is available");
        return fmi2Error;
    }
    *value = inst->joint->time;
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
        joint_log(inst->joint, fmi2Error, "%s: doStep never returns fmi2Pending here", #function);   \
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
        joint_log(inst->joint, fmi2Error, "%s: %s", #function, reason); \
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
NOT_PROVIDED(fmi2GetDirectionalDerivative,
             (fmi2Component c, const fmi2ValueReference unknown[], size_t n_unknown, const fmi2ValueReference known[],
              size_t n_known, const fmi2Real dv_known[], fmi2Real dv_unknown[]),
             "providesDirectionalDerivative is false for this FMU")

/* ------------------------------------------------------------------ Model Exchange */
fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2EnterEventMode", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi2Error;
    inst->mode = MODE_EVENT;
    return fmi2OK;
}

/* A state event (a contact begins or ends): the contact-onset bookkeeping at the current inputs. */
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2NewDiscreteStates", M(MODE_EVENT)))
        return fmi2Error;
    if (info == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2NewDiscreteStates: NULL eventInfo");
        return fmi2Error;
    }
    memset(info, 0, sizeof *info);
    return joint_update_contact_memory(inst->joint, "fmi2NewDiscreteStates") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2EnterContinuousTimeMode", M(MODE_EVENT)))
        return fmi2Error;
    inst->mode = MODE_CONTINUOUS;
    return fmi2OK;
}

/* Wear and the onset bookkeeping over the step since the last completed one, at the current inputs. */
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set_state_prior, fmi2Boolean *enter_event_mode,
                                       fmi2Boolean *terminate_simulation)
{
    Instance *inst = c;
    (void)no_set_state_prior;
    if (inst == NULL || !mode_is(inst, "fmi2CompletedIntegratorStep", M(MODE_CONTINUOUS)))
        return fmi2Error;
    if (enter_event_mode == NULL || terminate_simulation == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2CompletedIntegratorStep: NULL output pointer");
        return fmi2Error;
    }
    *enter_event_mode = fmi2False;
    *terminate_simulation = fmi2False;
    return (fmi2Status)joint_completed_integrator_step(inst->joint, "fmi2CompletedIntegratorStep");
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2SetTime", M(MODE_EVENT) | M(MODE_CONTINUOUS)))
        return fmi2Error;
    return joint_set_time(inst->joint, time, "fmi2SetTime") ? fmi2OK : fmi2Error;
}

/* This FMU has no continuous states: nx must be 0. */
static int no_states(const Instance *inst, const char *function, size_t nx)
{
    if (inst == NULL)
        return 0;
    if (nx == 0)
        return 1;
    joint_log(inst->joint, fmi2Error, "%s: this FMU has no continuous states (nx=%zu given)", function, nx);
    return 0;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    (void)x;
    return no_states(c, "fmi2SetContinuousStates", nx) ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    (void)derivatives;
    return no_states(c, "fmi2GetDerivatives", nx) ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    (void)x;
    return no_states(c, "fmi2GetContinuousStates", nx) ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    (void)x_nominal;
    return no_states(c, "fmi2GetNominalsOfContinuousStates", nx) ? fmi2OK : fmi2Error;
}

/* The event indicator: the signed penetration of the deepest bushing point at the current inputs. */
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real indicators[], size_t ni)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2GetEventIndicators", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    if (ni != N_EVENT_INDICATORS || indicators == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2GetEventIndicators: this FMU has %d event indicator (ni=%zu given)",
                  N_EVENT_INDICATORS, ni);
        return fmi2Error;
    }
    return joint_event_indicator(inst->joint, "fmi2GetEventIndicators", &indicators[0]) ? fmi2OK : fmi2Error;
}

/* ------------------------------------------------------------------ FMU state */
static FmuState *new_state(const Instance *inst)
{
    size_t size = joint_state_size(inst->joint);
    FmuState *s = allocate((void *)&inst->callbacks, 1, sizeof *s + size);
    if (s == NULL)
        joint_log(inst->joint, fmi2Error, "FMU state: out of memory");
    else
        s->size = size;
    return s;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (state == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2GetFMUstate: NULL state pointer");
        return fmi2Error;
    }
    FmuState *s = *state;
    if (s == NULL) {
        if ((s = new_state(inst)) == NULL)
            return fmi2Error;
        *state = s;
    } else if (s->size != joint_state_size(inst->joint)) {
        joint_log(inst->joint, fmi2Error, "fmi2GetFMUstate: the state given to overwrite is not of this FMU");
        return fmi2Error;
    }
    joint_write_state(inst->joint, s->bytes, (M(inst->mode) & INITIALISED) != 0);
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const FmuState *s = state;
    if (s == NULL || s->size != joint_state_size(inst->joint)) {
        joint_log(inst->joint, fmi2Error, "fmi2SetFMUstate: NULL or not a state of this FMU");
        return fmi2Error;
    }
    int initialised = 0;
    int ok = joint_read_state(inst->joint, s->bytes, &initialised, "fmi2SetFMUstate");
    if (initialised && !(M(inst->mode) & (M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | M(MODE_CONTINUOUS))))
        inst->mode = inst->type == fmi2CoSimulation ? MODE_STEP_COMPLETE : MODE_EVENT;
    else if (!initialised && (M(inst->mode) & INITIALISED))
        inst->mode = MODE_INITIALIZATION;
    return ok ? fmi2OK : fmi2Error;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (state == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2FreeFMUstate: NULL state pointer");
        return fmi2Error;
    }
    release(&inst->callbacks, *state);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const FmuState *s = state;
    if (s == NULL || size == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2SerializedFMUstateSize: NULL state or size pointer");
        return fmi2Error;
    }
    *size = s->size;
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const FmuState *s = state;
    if (s == NULL || bytes == NULL || size < s->size) {
        joint_log(inst->joint, fmi2Error,
                  "fmi2SerializeFMUstate: NULL state or buffer, or a buffer of %zu bytes for a state of %zu", size,
                  s != NULL ? s->size : (size_t)0);
        return fmi2Error;
    }
    memcpy(bytes, s->bytes, s->size);
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (bytes == NULL || state == NULL) {
        joint_log(inst->joint, fmi2Error, "fmi2DeSerializeFMUstate: NULL bytes or state pointer");
        return fmi2Error;
    }
    if (!joint_state_valid(inst->joint, bytes, size, "fmi2DeSerializeFMUstate"))
        return fmi2Error;
    FmuState *s = *state;
    if (s != NULL && s->size != size) {
        joint_log(inst->joint, fmi2Error, "fmi2DeSerializeFMUstate: the state given to overwrite is not of this FMU");
        return fmi2Error;
    }
    if (s == NULL && (s = new_state(inst)) == NULL)
        return fmi2Error;
    memcpy(s->bytes, bytes, size);
    *state = s;
    return fmi2OK;
}
