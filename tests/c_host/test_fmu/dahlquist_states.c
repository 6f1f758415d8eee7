/* dahlquist_states.c -- the test FMU's FMU states (get, set, free, serialise) and status queries;
 * the model and its other functions: dahlquist.c. */
#include <string.h>

#include "dahlquist.h"

/* ------------------------------------------------------------------------- */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    Instance *inst = c;
    State *s;
    if (inst == NULL)
        return fmi2Error;
    if (FMUstate == NULL)
        ERROR(inst, "fmi2GetFMUstate: NULL FMUstate pointer");
    s = *FMUstate;
    if (s == NULL) {
        s = inst->cb->allocateMemory(1, sizeof *s);
        if (s == NULL)
            ERROR(inst, "fmi2GetFMUstate: out of memory");
        memcpy(s->magic, MAGIC, 8);
    } else if (memcmp(s->magic, MAGIC, 8) != 0) {
        ERROR(inst, "fmi2GetFMUstate: *FMUstate is not a state of this FMU");
    }
    s->d = inst->d;
    *FMUstate = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    Instance *inst = c;
    const State *s = FMUstate;
    if (inst == NULL)
        return fmi2Error;
    if (s == NULL || memcmp(s->magic, MAGIC, 8) != 0)
        ERROR(inst, "fmi2SetFMUstate: NULL or foreign FMUstate");
    inst->d = s->d;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (FMUstate == NULL)
        ERROR(inst, "fmi2FreeFMUstate: NULL FMUstate pointer");
    if (*FMUstate == NULL)
        return fmi2OK;
    inst->cb->freeMemory(*FMUstate);
    *FMUstate = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (FMUstate == NULL || size == NULL)
        ERROR(inst, "fmi2SerializedFMUstateSize: NULL argument");
    *size = SERIALIZED_SIZE;
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    Instance *inst = c;
    const State *s = FMUstate;
    char *p = serializedState;
    if (inst == NULL)
        return fmi2Error;
    if (s == NULL || serializedState == NULL || memcmp(s->magic, MAGIC, 8) != 0)
        ERROR(inst, "fmi2SerializeFMUstate: NULL argument or foreign FMUstate");
    if (size < SERIALIZED_SIZE)
        ERROR(inst, "fmi2SerializeFMUstate: buffer of %zu bytes, need %d", size, SERIALIZED_SIZE);
    memcpy(p, MAGIC, 8), p += 8;
    memcpy(p, &s->d.time, 8), p += 8;
    memcpy(p, &s->d.x, 8), p += 8;
    memcpy(p, &s->d.k, 8), p += 8;
    memcpy(p, &s->d.x0, 8), p += 8;
    memcpy(p, &s->d.u, 8), p += 8;
    memcpy(p, &s->d.n_steps, 4), p += 4;
    memcpy(p, &s->d.phase, 4);
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    Instance *inst = c;
    const char *p = serializedState;
    State *s;
    if (inst == NULL)
        return fmi2Error;
    if (serializedState == NULL || FMUstate == NULL)
        ERROR(inst, "fmi2DeSerializeFMUstate: NULL argument");
    if (size != SERIALIZED_SIZE || memcmp(p, MAGIC, 8) != 0)
        ERROR(inst, "fmi2DeSerializeFMUstate: not a serialized state of this FMU (%zu bytes)", size);
    s = *FMUstate;
    if (s == NULL) {
        s = inst->cb->allocateMemory(1, sizeof *s);
        if (s == NULL)
            ERROR(inst, "fmi2DeSerializeFMUstate: out of memory");
    }
    memcpy(s->magic, MAGIC, 8), p += 8;
    memcpy(&s->d.time, p, 8), p += 8;
    memcpy(&s->d.x, p, 8), p += 8;
    memcpy(&s->d.k, p, 8), p += 8;
    memcpy(&s->d.x0, p, 8), p += 8;
    memcpy(&s->d.u, p, 8), p += 8;
    memcpy(&s->d.n_steps, p, 4), p += 4;
    memcpy(&s->d.phase, p, 4);
    *FMUstate = s;
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    Instance *inst = c;
    (void)vUnknown_ref, (void)nUnknown, (void)vKnown_ref, (void)nKnown, (void)dvKnown, (void)dvUnknown;
    if (inst == NULL)
        return fmi2Error;
    ERROR(inst, "fmi2GetDirectionalDerivative: not supported");
}


fmi2Status fmi2CancelStep(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    ERROR(inst, "fmi2CancelStep: no asynchronous step to cancel");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    Instance *inst = c;
    (void)s;
    if (inst == NULL)
        return fmi2Error;
    if (value == NULL)
        ERROR(inst, "fmi2GetStatus: NULL value");
    return fmi2Discard;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (value == NULL)
        ERROR(inst, "fmi2GetRealStatus: NULL value");
    if (s != fmi2LastSuccessfulTime)
        return fmi2Discard;
    *value = inst->d.time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    Instance *inst = c;
    (void)s;
    if (inst == NULL)
        return fmi2Error;
    if (value == NULL)
        ERROR(inst, "fmi2GetIntegerStatus: NULL value");
    return fmi2Discard;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (value == NULL)
        ERROR(inst, "fmi2GetBooleanStatus: NULL value");
    if (s != fmi2Terminated)
        return fmi2Discard;
    *value = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    Instance *inst = c;
    (void)s;
    if (inst == NULL)
        return fmi2Error;
    if (value == NULL)
        ERROR(inst, "fmi2GetStringStatus: NULL value");
    return fmi2Discard;
}
