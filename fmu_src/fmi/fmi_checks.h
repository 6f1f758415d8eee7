/* What the FMI 2.0 and 3.0 layers share (fmi2_instance.h, fmi3_instance.h): the checks every FMI call
 * makes, the mode changes and the messages of a call the FMU refuses.  Included after the version's
 * Instance (with ``model`` and ``mode``), M(), MODE_NAMES, LOG, FMI_VERSION (2 or 3), FMI_STATUS (its
 * status type), MODE_STEPPING (Co-Simulation's mode between steps), IS_CO_SIMULATION(inst) and
 * FMI_CALL_SEQUENCE (the call sequence's name for messages). */
#ifndef WEARJOINT_FMI_CHECKS_H
#define WEARJOINT_FMI_CHECKS_H

#include <float.h>
#include <math.h>
#include <stddef.h>

#include "fmu_model.h"
#include "model_variables.h"

static inline int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    LOG(inst, FMU_ERROR, "%s: not allowed in state %s (" FMI_CALL_SEQUENCE ")", function,
              MODE_NAMES[inst->mode]);
    return 0;
}

/* A call that moves the instance from one of ``modes`` to ``next``: FMU_OK, or FMU_ERROR (logged where
 * possible) without an instance or from another mode. */
static inline int change_mode(Instance *inst, const char *function, unsigned modes, Mode next)
{
    if (inst == NULL || !mode_is(inst, function, modes))
        return FMU_ERROR;
    inst->mode = next;
    return FMU_OK;
}

/* The experiment's start and stop time (fmi2SetupExperiment, fmi3EnterInitializationMode): the start finite, a
 * defined stop not before it; the stop kept for step_allowed (INFINITY if not defined).  1, or 0 logged. */
static inline int start_and_stop_time(Instance *inst, const char *function, double start, int stop_defined,
                                      double stop)
{
    if (!isfinite(start)) {
        LOG(inst, FMU_ERROR, "%s: startTime=%g is invalid: allowed a finite time", function, start);
        return 0;
    }
    if (stop_defined && !(stop >= start)) {
        LOG(inst, FMU_ERROR, "%s: stopTime=%g is invalid: allowed a time >= startTime=%g", function, stop, start);
        return 0;
    }
    inst->stop_time = stop_defined ? stop : INFINITY;
    return 1;
}

/* A Co-Simulation step from t over h: from the FMU's time (the start time, the end of its last step or the time of
 * a state set; to rounding, a thousandth of the step) and not past the stop time (as much).  A master that lost or
 * repeated a step, or runs past its own stop time, is told: 1, or 0 logged. */
static inline int step_allowed(const Instance *inst, const char *function, double t, double h)
{
    if (!isfinite(h))
        return 1;   /* the model refuses the step itself, naming h (fmi2Discard, as a negative one) */
    double time = model_time(inst->model);
    double slack = 1e-3 * fabs(h) + 4.0 * DBL_EPSILON * fmax(fabs(t), fabs(time));
    if (!(fabs(t - time) <= slack)) {
        LOG(inst, FMU_ERROR, "%s: currentCommunicationPoint=%.17g s is invalid: allowed the FMU's time %.17g s (the "
            "start time, the end of its last step or a state's time set): a step was lost or repeated", function, t,
            time);
        return 0;
    }
    if (t + h > inst->stop_time + slack) {
        LOG(inst, FMU_ERROR, "%s: a step of %g s from %.17g s ends past the stop time %.17g s the master set: "
            "allowed up to it", function, h, t, inst->stop_time);
        return 0;
    }
    return 1;
}

/* The mode an initialised instance runs in: between steps (Co-Simulation) or Event Mode (Model Exchange). */
static inline Mode running_mode(const Instance *inst)
{
    return IS_CO_SIMULATION(inst) ? MODE_STEPPING : MODE_EVENT;
}

/* The mode after an FMU state was restored, from the state's ``initialised`` flag (1, 0, or -1 if none was
 * read): an initialised state makes a running instance, an uninitialised one an initialising instance. */
static inline void mode_after_set_state(Instance *inst, int initialised)
{
    if (initialised == 1 && !(M(inst->mode) & (M(MODE_STEPPING) | M(MODE_EVENT) | M(MODE_CONTINUOUS))))
        inst->mode = running_mode(inst);
    else if (initialised == 0 && (M(inst->mode) & INITIALISED))
        inst->mode = MODE_INITIALIZATION;
}

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static inline int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr,
                               const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        LOG(inst, FMU_ERROR, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

/* A valid instance with the model's N_CONTINUOUS_STATES states: nx must be that, x given for nx > 0. */
static inline int states_given(const Instance *inst, const char *function, size_t nx, const void *x)
{
    if (inst == NULL)
        return 0;
    if (nx != N_CONTINUOUS_STATES) {
        if (N_CONTINUOUS_STATES == 0)
            LOG(inst, FMU_ERROR, "%s: this FMU has no continuous states (nx=%zu given)", function, nx);
        else
            LOG(inst, FMU_ERROR, "%s: this FMU has %d continuous states (nx=%zu given)", function,
                N_CONTINUOUS_STATES, nx);
        return 0;
    }
    if (nx > 0 && x == NULL) {
        LOG(inst, FMU_ERROR, "%s: NULL array", function);
        return 0;
    }
    return 1;
}

/* The model's N_EVENT_INDICATORS event indicators into ``indicators`` (ni of them): FMU_OK or FMU_ERROR (logged). */
static inline int get_event_indicators(Instance *inst, const char *function, double indicators[], size_t ni)
{
    if (inst == NULL || !mode_is(inst, function, M(MODE_INITIALIZATION) | INITIALISED))
        return FMU_ERROR;
    if (ni != N_EVENT_INDICATORS || (ni > 0 && indicators == NULL)) {
        LOG(inst, FMU_ERROR, "%s: this FMU has %d event indicator%s (ni=%zu given)", function, N_EVENT_INDICATORS,
            N_EVENT_INDICATORS == 1 ? "" : "s", ni);
        return FMU_ERROR;
    }
    if (ni == 0)
        return FMU_OK;
    return model_get_event_indicators(inst->model, indicators, function) ? FMU_OK : FMU_ERROR;
}

/* Every state's nominal value, 1. */
static inline int get_nominals(const Instance *inst, const char *function, double nominals[], size_t nx)
{
    if (!states_given(inst, function, nx, nominals))
        return FMU_ERROR;
    for (size_t i = 0; i < nx; i++)
        nominals[i] = 1.0;
    return FMU_OK;
}

/* A parameter may be set before ExitInitializationMode only. */
static inline int parameters_settable(const Instance *inst)
{
    return inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION;
}

/* The message of a get (``setting`` 0) or set (1) of ``vr`` that the model refused with ``done`` (model_get_*,
 * model_set_*: -1 not ``a_type`` variable (e.g. "a Real") that can be got or set, -2 a parameter after
 * initialisation; 0 it logged itself); FMU_ERROR. */
static inline int access_refused(const Instance *inst, const char *function, unsigned vr, const char *a_type,
                                 int setting, int done)
{
    char name[96];
    model_variable_name(inst->model, FMI_VERSION, vr, name, sizeof name);
    if (done == -1 && setting)
        LOG(inst, FMU_ERROR, "%s: %s cannot be set (it is not %s input or parameter)", function, name, a_type);
    else if (done == -1)
        LOG(inst, FMU_ERROR, "%s: %s is not %s variable", function, name, a_type);
    else if (done == -2)
        LOG(inst, FMU_ERROR, "%s: parameter %s is fixed: set it before fmi%dExitInitializationMode", function, name,
            FMI_VERSION);
    return FMU_ERROR;
}

/* A get or set of a type this FMU has no variables of: FMU_OK for none, else FMU_ERROR (logged). */
static inline int no_variables_of_type(const Instance *inst, const char *function, const char *type, size_t nvr,
                                       const unsigned vr[], const void *value)
{
    if (!arrays_given(inst, function, nvr, vr, value))
        return FMU_ERROR;
    if (nvr == 0)
        return FMU_OK;
    LOG(inst, FMU_ERROR, "%s: this FMU has no %s variables (valueReference %u)", function, type, vr[0]);
    return FMU_ERROR;
}

/* A function this FMU does not provide, its ``instance`` the name of its instance argument in ``parameters``:
 * it logs ``reason`` and returns an error.  (The other parameters are named for the reader, unused.) */
#define NOT_PROVIDED(function, instance, parameters, reason)          \
    FMI_STATUS function parameters                                    \
    {                                                                 \
        Instance *inst = instance;                                    \
        if (inst != NULL)                                             \
            LOG(inst, FMU_ERROR, "%s: %s", #function, reason);        \
        return (FMI_STATUS)FMU_ERROR;                                 \
    }

#endif
