/* FMI 2.0 layer (fmi2Functions.c): the Co-Simulation calls -- fmi2DoStep (the model's step; a step
 * it cannot take gives fmi2Discard, state unchanged), the status queries, and what this FMU does not
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
