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
 *
 * The layer's files: this one the host callbacks, the instance's lifetime and the FMU states;
 * fmi2_values.c the variables' values and directional derivatives; fmi2_cosimulation.c and
 * fmi2_model_exchange.c the calls of each interface; fmi2_instance.h what they share (the
 * instance, its modes, the checks every call makes).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_instance.h"
#include "fmi_state_functions.h"

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
    inst->stop_time = INFINITY;
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
    if (inst == NULL)
        return fmi2Error;
    /* FMI 2.0: "If loggingOn=fmi2True and nCategories > 0, then only debug messages according to the categories
     * argument shall be printed." */
    return fmu_set_debug_logging(model_host(inst->model), logging_on, n_categories, categories, logging_on,
                                 "fmi2SetDebugLogging") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance,
                               fmi2Real start_time, fmi2Boolean stop_time_defined, fmi2Real stop_time)
{
    Instance *inst = c;
    (void)tolerance_defined;
    (void)tolerance;
    if (inst == NULL || !mode_is(inst, "fmi2SetupExperiment", M(MODE_INSTANTIATED)))
        return fmi2Error;
    if (!start_and_stop_time(inst, "fmi2SetupExperiment", start_time, stop_time_defined, stop_time))
        return fmi2Error;
    model_set_start_time(inst->model, start_time);
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    return (fmi2Status)change_mode(c, "fmi2EnterInitializationMode", M(MODE_INSTANTIATED), MODE_INITIALIZATION);
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2ExitInitializationMode", M(MODE_INITIALIZATION)))
        return fmi2Error;
    if (!model_exit_initialization(inst->model, "fmi2ExitInitializationMode"))
        return fmi2Error;
    inst->mode = running_mode(inst);
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    return (fmi2Status)change_mode(c, "fmi2Terminate", READABLE, MODE_TERMINATED);
}

fmi2Status fmi2Reset(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (!model_reset(inst->model))
        return fmi2Error;
    inst->mode = MODE_INSTANTIATED;
    inst->discarded = fmi2False;
    inst->stop_time = INFINITY;
    return fmi2OK;
}

/* ------------------------------------------------------------------ FMU state (fmu_state.c) */
FMU_STATE_FUNCTIONS(fmi2Status, fmi2Component, fmi2FMUstate, fmi2Byte, fmi2GetFMUstate, fmi2SetFMUstate,
                    fmi2FreeFMUstate, fmi2SerializedFMUstateSize, fmi2SerializeFMUstate, fmi2DeSerializeFMUstate,
                    ~0u)
