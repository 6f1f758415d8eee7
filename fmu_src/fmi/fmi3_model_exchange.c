/* FMI 3.0 layer (fmi3Functions.c): the Model Exchange calls -- the model's event update and
 * accepted-step bookkeeping, continuous-time mode, time, continuous states and event indicators (the
 * model's N_CONTINUOUS_STATES and N_EVENT_INDICATORS, model_variables.h; the checks in fmi_checks.h).
 */
#include "fmi3_instance.h"

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
    return (fmi3Status)change_mode(instance, "fmi3EnterContinuousTimeMode", M(MODE_EVENT), MODE_CONTINUOUS);
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
    return (fmi3Status)get_nominals(instance, "fmi3GetNominalsOfContinuousStates", nominals, nx);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t ni)
{
    return (fmi3Status)get_event_indicators(instance, "fmi3GetEventIndicators", indicators, ni);
}

/* The number of the model's event indicators, continuous states: ``count`` into *n. */
static fmi3Status number_of(const Instance *inst, const char *function, size_t count, size_t *n)
{
    if (inst == NULL)
        return fmi3Error;
    if (n == NULL) {
        LOG(inst, fmi3Error, "%s: NULL pointer", function);
        return fmi3Error;
    }
    *n = count;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n)
{
    return number_of(instance, "fmi3GetNumberOfEventIndicators", N_EVENT_INDICATORS, n);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n)
{
    return number_of(instance, "fmi3GetNumberOfContinuousStates", N_CONTINUOUS_STATES, n);
}
