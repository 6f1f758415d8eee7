/* The checks every FMI call makes, shared by the FMI 2.0 and 3.0 layers (fmi2_instance.h, fmi3_instance.h):
 * included after the version's Instance (with ``model`` and ``mode``), M(), MODE_NAMES, LOG and
 * FMI_CALL_SEQUENCE (the call sequence's name for messages). */
#ifndef WEARJOINT_FMI_CHECKS_H
#define WEARJOINT_FMI_CHECKS_H

#include <stddef.h>

#include "fmu_model.h"

static inline int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    if (modes & M(inst->mode))
        return 1;
    LOG(inst, FMU_ERROR, "%s: not allowed in state %s (" FMI_CALL_SEQUENCE ")", function,
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
        LOG(inst, FMU_ERROR, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

#endif
