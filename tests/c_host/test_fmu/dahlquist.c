/*
 * dahlquist.c -- a tiny FMI 2.0 Co-Simulation FMU to test tests/c_host/fmi2_host.c.
 *
 *     x' = -k (x - u/k) = -k x + u,   x(t0) = x0
 *
 * Each fmi2DoStep(t, h) advances x with the exact solution for an input u held
 * constant over the step:
 *
 *     x <- u/k + (x - u/k) exp(-k h)      (k != 0)
 *     x <- x + u h                        (k == 0)
 *
 * so with u = 0 the outputs equal x0 exp(-k t) up to rounding.
 *
 * Value references
 *   0 x          Real     output, continuous, initial calculated (= x0)
 *   1 k          Real     parameter, fixed, start 1   (k < 0: accepted with a warning)
 *   2 x0         Real     parameter, fixed, start 1
 *   3 u          Real     input, continuous, start 0
 *   4 n_steps    Integer  output, discrete, start 0   (successful doSteps)
 *   5 resource   String   calculatedParameter: the resourceLocation passed to
 *                         fmi2Instantiate
 *
 * Checks (all return fmi2Error and log unless noted): NULL component/arrays,
 * unknown value references, out-of-order calls (the FMI 2.0 CS state machine),
 * fmi2DoStep at a time other than the FMU's time, h <= 0; h > 10 returns
 * fmi2Discard (state unchanged).  FMU states: get (reusing *FMUstate),
 * set, free (sets *FMUstate = NULL), serialize/deserialize (56 bytes).
 * Memory comes from the importer's allocateMemory/freeMemory.  Compiled with
 * -DDAHLQUIST_LEAK, fmi2FreeInstance leaks the instance name (a deliberate bug
 * that the valgrind test must detect).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "dahlquist.h"


static void defaults(Data *d)
{
    d->time = 0.0;
    d->k = 1.0;
    d->x0 = 1.0;
    d->x = d->x0;
    d->u = 0.0;
    d->n_steps = 0;
    d->phase = INSTANTIATED;
}

static char *dup_string(const fmi2CallbackFunctions *cb, const char *s)
{
    size_t n = strlen(s) + 1;
    char *p = cb->allocateMemory(n, 1);
    if (p != NULL)
        memcpy(p, s, n);
    return p;
}

/* ------------------------------------------------------------------------- */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    Instance *inst;
    (void)visible;
    if (functions == NULL || functions->allocateMemory == NULL || functions->freeMemory == NULL)
        return NULL;
    if (instanceName == NULL || instanceName[0] == '\0') {
        if (functions->logger != NULL)
            functions->logger(functions->componentEnvironment, "?", fmi2Error, "logStatusError",
                              "fmi2Instantiate: missing instance name");
        return NULL;
    }
    if (fmuType != fmi2CoSimulation || fmuGUID == NULL || strcmp(fmuGUID, GUID) != 0) {
        if (functions->logger != NULL)
            functions->logger(functions->componentEnvironment, instanceName, fmi2Error, "logStatusError",
                              "fmi2Instantiate: wrong FMU type or GUID '%s' (expected %s)",
                              fmuGUID ? fmuGUID : "(null)", GUID);
        return NULL;
    }
    inst = functions->allocateMemory(1, sizeof *inst);
    if (inst == NULL)
        return NULL;
    inst->cb = functions;
    inst->logging = loggingOn;
    inst->name = dup_string(functions, instanceName);
    inst->resource = dup_string(functions, fmuResourceLocation ? fmuResourceLocation : "");
    if (inst->name == NULL || inst->resource == NULL) {
        functions->freeMemory(inst->name);
        functions->freeMemory(inst->resource);
        functions->freeMemory(inst);
        return NULL;
    }
    defaults(&inst->d);
    LOG(inst, fmi2OK, "logAll", "fmi2Instantiate: '%s', resources at %s", inst->name, inst->resource);
    return inst;
}

void fmi2FreeInstance(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return;
#ifndef DAHLQUIST_LEAK /* -DDAHLQUIST_LEAK: leak the name, to show the valgrind check bites */
    inst->cb->freeMemory(inst->name);
#endif
    inst->cb->freeMemory(inst->resource);
    inst->cb->freeMemory(inst);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    Instance *inst = c;
    (void)nCategories;
    (void)categories;
    if (inst == NULL)
        return fmi2Error;
    inst->logging = loggingOn;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    Instance *inst = c;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (inst == NULL)
        return fmi2Error;
    ALLOWED(inst, "fmi2SetupExperiment", INSTANTIATED);
    inst->d.time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    ALLOWED(inst, "fmi2EnterInitializationMode", INSTANTIATED);
    inst->d.phase = INIT_MODE;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    ALLOWED(inst, "fmi2ExitInitializationMode", INIT_MODE);
    inst->d.x = inst->d.x0;
    inst->d.phase = STEP_MODE;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    ALLOWED(inst, "fmi2Terminate", STEP_MODE);
    inst->d.phase = TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    defaults(&inst->d);
    return fmi2OK;
}

/* ------------------------------------------------------------------------- */

#define CHECK_ARRAYS(inst, fn, vr, nvr, value)                                             \
    do {                                                                                   \
        if ((inst) == NULL)                                                                \
            return fmi2Error;                                                              \
        if ((nvr) > 0 && ((vr) == NULL || (value) == NULL))                                \
            ERROR(inst, "%s: NULL array", fn);                                             \
    } while (0)

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2GetReal", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ALLOWED(inst, "fmi2GetReal", INIT_MODE | STEP_MODE | TERMINATED);
    for (size_t i = 0; i < nvr; i++) {
        switch (vr[i]) {
        case VR_X: value[i] = inst->d.phase == INIT_MODE ? inst->d.x0 : inst->d.x; break;
        case VR_K: value[i] = inst->d.k; break;
        case VR_X0: value[i] = inst->d.x0; break;
        case VR_U: value[i] = inst->d.u; break;
        default: ERROR(inst, "fmi2GetReal: unknown value reference %u", vr[i]);
        }
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2GetInteger", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ALLOWED(inst, "fmi2GetInteger", INIT_MODE | STEP_MODE | TERMINATED);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] != VR_NSTEPS)
            ERROR(inst, "fmi2GetInteger: unknown value reference %u", vr[i]);
        value[i] = inst->d.n_steps;
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2GetBoolean", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ERROR(inst, "fmi2GetBoolean: unknown value reference %u", vr[0]);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2GetString", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ALLOWED(inst, "fmi2GetString", INIT_MODE | STEP_MODE | TERMINATED);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] != VR_RESOURCE)
            ERROR(inst, "fmi2GetString: unknown value reference %u", vr[i]);
        value[i] = inst->resource;
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Instance *inst = c;
    fmi2Status status = fmi2OK;
    CHECK_ARRAYS(inst, "fmi2SetReal", vr, nvr, value);
    for (size_t i = 0; i < nvr; i++) {
        if (!isfinite(value[i]))
            ERROR(inst, "fmi2SetReal: value of %u is not finite", vr[i]);
        switch (vr[i]) {
        case VR_K:
            ALLOWED(inst, "fmi2SetReal(k)", INSTANTIATED | INIT_MODE);
            if (value[i] < 0) {
                LOG(inst, fmi2Warning, "logStatusWarning", "fmi2SetReal: k = %g < 0 makes x grow", value[i]);
                status = fmi2Warning;
            }
            inst->d.k = value[i];
            break;
        case VR_X0:
            ALLOWED(inst, "fmi2SetReal(x0)", INSTANTIATED | INIT_MODE);
            inst->d.x0 = value[i];
            break;
        case VR_U:
            ALLOWED(inst, "fmi2SetReal(u)", INSTANTIATED | INIT_MODE | STEP_MODE);
            inst->d.u = value[i];
            break;
        default:
            ERROR(inst, "fmi2SetReal: value reference %u is unknown or not settable", vr[i]);
        }
    }
    return status;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2SetInteger", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ERROR(inst, "fmi2SetInteger: value reference %u is unknown or not settable", vr[0]);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2SetBoolean", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ERROR(inst, "fmi2SetBoolean: value reference %u is unknown or not settable", vr[0]);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    Instance *inst = c;
    CHECK_ARRAYS(inst, "fmi2SetString", vr, nvr, value);
    if (nvr == 0)
        return fmi2OK;
    ERROR(inst, "fmi2SetString: value reference %u is unknown or not settable", vr[0]);
}

/* ------------------------------------------------------------------------- */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    Instance *inst = c;
    (void)vr, (void)nvr, (void)order, (void)value;
    if (inst == NULL)
        return fmi2Error;
    ERROR(inst, "fmi2SetRealInputDerivatives: not supported");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    Instance *inst = c;
    (void)vr, (void)nvr, (void)order, (void)value;
    if (inst == NULL)
        return fmi2Error;
    ERROR(inst, "fmi2GetRealOutputDerivatives: not supported");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    Instance *inst = c;
    Data *d;
    double t = currentCommunicationPoint, h = communicationStepSize;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst == NULL)
        return fmi2Error;
    d = &inst->d;
    ALLOWED(inst, "fmi2DoStep", STEP_MODE);
    if (!(h > 0.0) || !isfinite(h))
        ERROR(inst, "fmi2DoStep: communicationStepSize %.17g is not positive", h);
    if (!(fabs(t - d->time) <= 1e-9 * fmax(1.0, fabs(d->time))))
        ERROR(inst, "fmi2DoStep: currentCommunicationPoint %.17g does not match the FMU time %.17g", t, d->time);
    if (h > 10.0) {
        LOG(inst, fmi2Discard, "logStatusDiscard", "fmi2DoStep: step %g > 10 refused", h);
        return fmi2Discard;
    }
    if (d->k != 0.0) {
        double xeq = d->u / d->k;
        d->x = xeq + (d->x - xeq) * exp(-d->k * h);
    } else {
        d->x += d->u * h;
    }
    d->time = t + h;
    d->n_steps++;
    return fmi2OK;
}

