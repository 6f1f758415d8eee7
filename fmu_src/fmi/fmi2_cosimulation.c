/* FMI 2.0 layer (fmi2Functions.c): the Co-Simulation calls -- fmi2DoStep (the model's step; a step
 * it cannot take gives fmi2Discard, state unchanged), the status queries (after fmi2Discard: fmi2Terminated and
 * fmi2LastSuccessfulTime), and what this FMU does not
 * provide (asynchronous steps, input and output derivatives).
 */
#include <math.h>

#include "fmi2_instance.h"

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real current_time, fmi2Real step_size, fmi2Boolean no_set_state_before)
{
    Instance *inst = c;
    (void)no_set_state_before;
    if (inst == NULL || !mode_is(inst, "fmi2DoStep", M(MODE_STEP_COMPLETE)))
        return fmi2Error;
    fmi2Status status = fmi2Discard;
    if (!isfinite(current_time))
        LOG(inst, fmi2Error, "fmi2DoStep: currentCommunicationPoint=%g is not finite", current_time);
    else if (!step_allowed(inst, "fmi2DoStep", current_time, step_size))
        status = fmi2Error;
    else
        status = (fmi2Status)model_do_step(inst->model, current_time, step_size, "fmi2DoStep");
    inst->discarded = status == fmi2Discard;
    return status;
}

/* A status query's checks: an instance, a value to write and the one kind available (else logged). */
static int status_query(Instance *inst, const void *value, fmi2StatusKind kind, fmi2StatusKind available,
                        const char *function, const char *name)
{
    if (inst == NULL || value == NULL)
        return 0;
    if (kind != available)
        LOG(inst, fmi2Error, "%s: only %s is available", function, name);
    return kind == available;
}

/* After fmi2Discard a master asks whether the slave wants the simulation to end: it does, as the step it refused
 * (the inputs' state is no contact of the joint's materials, or not finite) cannot be taken again; a master that
 * can go back (fmi2SetFMUstate) and retry another step does not need to ask. */
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value)
{
    if (!status_query(c, value, kind, fmi2Terminated, "fmi2GetBooleanStatus", "fmi2Terminated"))
        return fmi2Error;
    *value = ((Instance *)c)->discarded;
    return fmi2OK;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value)
{
    if (!status_query(c, value, kind, fmi2LastSuccessfulTime, "fmi2GetRealStatus", "fmi2LastSuccessfulTime"))
        return fmi2Error;
    *value = model_time(((Instance *)c)->model);
    return fmi2OK;
}

/* (the unused parameters of these functions are named, for the reader; -Wno-unused-parameter) */
#define NO_PENDING "doStep always completes synchronously here (never fmi2Pending)"
NOT_PROVIDED(fmi2CancelStep, c, (fmi2Component c), NO_PENDING)
NOT_PROVIDED(fmi2GetStatus, c, (fmi2Component c, const fmi2StatusKind kind, fmi2Status *value), NO_PENDING)
NOT_PROVIDED(fmi2GetIntegerStatus, c, (fmi2Component c, const fmi2StatusKind kind, fmi2Integer *value), NO_PENDING)
NOT_PROVIDED(fmi2GetStringStatus, c, (fmi2Component c, const fmi2StatusKind kind, fmi2String *value), NO_PENDING)
NOT_PROVIDED(fmi2SetRealInputDerivatives, c,
             (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer order[],
              const fmi2Real value[]),
             "canInterpolateInputs is false for this FMU")
NOT_PROVIDED(fmi2GetRealOutputDerivatives, c,
             (fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer order[],
              fmi2Real value[]),
             "maxOutputDerivativeOrder is 0 for this FMU")
