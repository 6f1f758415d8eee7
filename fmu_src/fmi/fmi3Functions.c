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
 *
 * The layer's files: this one the host callbacks, the instance's lifetime, Configuration Mode and
 * the FMU states; fmi3_values.c the variables' values and directional derivatives;
 * fmi3_not_provided.c the functions this FMU does not provide; fmi3_cosimulation.c and
 * fmi3_model_exchange.c the calls of each interface; fmi3_instance.h what they share (the
 * instance, its modes, the checks every call makes).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_instance.h"
#include "fmi_state_functions.h"

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

/* ------------------------------------------------------------------ lifetime */
const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean logging_on, size_t n_categories,
                               const fmi3String categories[])
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    /* FMI 3.0: "If nCategories > 0, loggingOn applies only to the specified categories." */
    return fmu_set_debug_logging(model_host(inst->model), logging_on, n_categories, categories, 0,
                                 "fmi3SetDebugLogging") ? fmi3OK : fmi3Error;
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
    inst->stop_time = INFINITY;
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
    if (inst == NULL || !mode_is(inst, "fmi3EnterInitializationMode", M(MODE_INSTANTIATED)))
        return fmi3Error;
    if (!start_and_stop_time(inst, "fmi3EnterInitializationMode", start_time, stop_time_defined, stop_time))
        return fmi3Error;
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
    inst->mode = running_mode(inst);
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
    return (fmi3Status)change_mode(inst, "fmi3EnterEventMode", M(MODE_EVENT) | M(MODE_CONTINUOUS), MODE_EVENT);
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    return (fmi3Status)change_mode(instance, "fmi3Terminate", READABLE, MODE_TERMINATED);
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
    inst->stop_time = INFINITY;
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

/* ------------------------------------------------------------------ FMU state (fmu_state.c, as FMI 2.0's) */
FMU_STATE_FUNCTIONS(fmi3Status, fmi3Instance, fmi3FMUState, fmi3Byte, fmi3GetFMUState, fmi3SetFMUState,
                    fmi3FreeFMUState, fmi3SerializedFMUStateSize, fmi3SerializeFMUState, fmi3DeserializeFMUState,
                    ~M(MODE_CONFIGURATION))
