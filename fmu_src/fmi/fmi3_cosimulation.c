/* FMI 3.0 layer (fmi3Functions.c): the Co-Simulation calls -- Step Mode and fmi3DoStep (the model's
 * step; no event mode, never an early return; a step it cannot take gives fmi3Discard, state
 * unchanged, still in Step Mode).
 */
#include <math.h>

#include "fmi3_instance.h"

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    Instance *inst = instance;
    if (inst == NULL)
        return fmi3Error;
    if (!inst->co_simulation) {
        LOG(inst, fmi3Error, "fmi3EnterStepMode: a Co-Simulation function, this is Model Exchange");
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
        LOG(inst, fmi3Error, "fmi3DoStep: NULL output pointer");
        return fmi3Error;
    }
    *event_handling_needed = fmi3False;
    *terminate_simulation = fmi3False;
    *early_return = fmi3False;
    *last_successful_time = model_time(inst->model);
    int status = fmi3Discard;
    if (!isfinite(current_time))
        LOG(inst, fmi3Error, "fmi3DoStep: currentCommunicationPoint=%g is not finite", current_time);
    else if (!step_allowed(inst, "fmi3DoStep", current_time, step_size))
        status = fmi3Error;
    else
        status = model_do_step(inst->model, current_time, step_size, "fmi3DoStep");
    *last_successful_time = model_time(inst->model);
    *terminate_simulation = status == fmi3Discard;   /* the refused step cannot be taken again (fmi2Terminated) */
    return (fmi3Status)status;
}
