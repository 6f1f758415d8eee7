/* FMI 2.0 layer (fmi2Functions.c): the Model Exchange calls -- event and continuous-time modes, the
 * model's event update and accepted-step bookkeeping, time, continuous states and event indicators
 * (the model's N_CONTINUOUS_STATES and N_EVENT_INDICATORS, model_variables.h; the checks in fmi_checks.h).
 */
#include <string.h>

#include "fmi2_instance.h"

fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    return (fmi2Status)change_mode(c, "fmi2EnterEventMode", M(MODE_EVENT) | M(MODE_CONTINUOUS), MODE_EVENT);
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
    return (fmi2Status)change_mode(c, "fmi2EnterContinuousTimeMode", M(MODE_EVENT), MODE_CONTINUOUS);
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
    if (!states_given(inst, "fmi2GetDerivatives", nx, derivatives) || !mode_is(inst, "fmi2GetDerivatives", READABLE))
        return fmi2Error;
    return model_get_derivatives(inst->model, derivatives, "fmi2GetDerivatives") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    Instance *inst = c;
    if (!states_given(inst, "fmi2GetContinuousStates", nx, x) || !mode_is(inst, "fmi2GetContinuousStates", READABLE))
        return fmi2Error;
    return model_get_continuous_states(inst->model, x, "fmi2GetContinuousStates") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    return (fmi2Status)get_nominals(c, "fmi2GetNominalsOfContinuousStates", x_nominal, nx);
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real indicators[], size_t ni)
{
    return (fmi2Status)get_event_indicators(c, "fmi2GetEventIndicators", indicators, ni);
}
