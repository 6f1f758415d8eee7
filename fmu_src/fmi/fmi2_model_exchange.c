/* FMI 2.0 layer (fmi2Functions.c): the Model Exchange calls -- event and continuous-time modes, the
 * model's event update and accepted-step bookkeeping, time, continuous states and event indicators
 * (the model's N_CONTINUOUS_STATES and N_EVENT_INDICATORS, model_variables.h).
 */
#include <string.h>

#include "fmi2_instance.h"
#include "model_variables.h"

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
