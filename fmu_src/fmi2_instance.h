/* The FMI 2.0 layer's instance, shared by the files of the layer (fmi2Functions.c, fmi2_values.c,
 * fmi2_cosimulation.c, fmi2_model_exchange.c): its modes (the FMI 2.0 call sequence), the model it
 * drives (fmu_model.h), the log macro and the checks every call makes.  Internal to the layer: the
 * checks are static inline, so the binary exports the fmi2* functions only.
 */
#ifndef WEARJOINT_FMI2_INSTANCE_H
#define WEARJOINT_FMI2_INSTANCE_H

#include <stddef.h>

#include "fmi2Functions.h"
#include "fmu_model.h"

typedef enum {
    MODE_INSTANTIATED, MODE_INITIALIZATION, MODE_STEP_COMPLETE, MODE_EVENT, MODE_CONTINUOUS, MODE_TERMINATED
} Mode;
static const char *const MODE_NAMES[] = {"instantiated", "initialization mode", "step complete", "event mode",
                                         "continuous-time mode", "terminated"};
#define M(mode) (1u << (mode))
#define INITIALISED (M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | M(MODE_CONTINUOUS) | M(MODE_TERMINATED))

typedef struct {
    FmuModel *model;
    fmi2CallbackFunctions callbacks;
    fmi2Type type;
    Mode mode;
} Instance;

#define LOG(inst, ...) fmu_log(model_host((inst)->model), __VA_ARGS__)

/* ------------------------------------------------------------------ checks shared by the calls */
static inline int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    LOG(inst, fmi2Error, "%s: not allowed in state %s (FMI 2.0 call sequence)", function,
              MODE_NAMES[inst->mode]);
    return 0;
}

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static inline int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr,
                               const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        LOG(inst, fmi2Error, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

#endif
