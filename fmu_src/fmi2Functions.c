/* FMI 2.0 Co-Simulation layer of the native ClearanceWearJoint FMU.
 *
 * Shaped like the Modelica Reference-FMUs' fmi2Functions.c: this file owns the instance
 * memory, the FMI 2.0 state machine, value references, status, logging and the FMU state;
 * the physics is the joint's numba kernels compiled ahead of time (model.h).  The variable
 * table (names, value references, start values, allowed ranges) is generated from
 * wearjoint/fmu/variables.py into model_variables.h by wearjoint/fmu/build_native.py.
 *
 * Semantics (docs/model.md, "The FMU"), the same as the pythonfmu backend's:
 * - outputs are direct feed-through: the forces are evaluated from the current inputs at
 *   the first getReal of a joint output after an input changed;
 * - doStep(t, h) accepts the step with the inputs held at t (wear, contact onsets);
 * - parameters are fixed at exitInitializationMode, where they are checked (fmi2Error with a
 *   message naming the variable and its allowed range);
 * - non-finite inputs: getReal of a joint output gives fmi2Error, doStep fmi2Discard (state
 *   unchanged); finite inputs set afterwards make the instance usable again;
 * - the FMU state is its serialised form (the pythonfmu backend's layout, so states move
 *   between the backends): magic, time, initialised flag, inputs, parameters, contact memory,
 *   wear depths, as float64.
 * Nothing is printed; every message goes to the host's logger.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "model.h"
#include "model_variables.h"

#define STATE_MAGIC "WJFMU002"
#define STATE_HEAD_DOUBLES 3 /* magic (8 bytes), time, initialised */
#define STATE_DOUBLES(n_points) (STATE_HEAD_DOUBLES + N_INPUTS + N_PARAMETERS + N_MEMORY + (size_t)(n_points))

typedef enum { MODE_INSTANTIATED, MODE_INITIALIZATION, MODE_STEP_COMPLETE, MODE_TERMINATED } Mode;

typedef struct {
    fmi2CallbackFunctions callbacks;
    char *name;
    fmi2Boolean logging_on;
    Mode mode;
    double time;
    double inputs[N_INPUTS];
    uint32_t non_finite_inputs;        /* bit i: input i is not finite */
    double parameters[N_PARAMETERS];   /* FMU parameter values (choices as their index) */
    int parameters_changed;            /* since the joint parameter vector was packed */
    int forces_stale;                  /* result does not belong to the current inputs */
    int wear_summary_stale;
    double max_wear_depth, worn_volume;
    int64_t n_points, n_blocks;
    double joint_parameters[N_JOINT_PARAMETERS];
    double memory[N_MEMORY];
    double result[N_RESULT];
    double *phi, *cos_phi, *sin_phi, *wear_depth, *block_min; /* one allocation, arrays */
    unsigned char *mask;
} Instance;

typedef struct {
    size_t size;
    unsigned char bytes[];
} FmuState;

/* ------------------------------------------------------------------ memory and logging */
static void *allocate(const fmi2CallbackFunctions *cb, size_t n, size_t size)
{
    return cb->allocateMemory != NULL ? cb->allocateMemory(n, size) : calloc(n, size);
}

static void release(const fmi2CallbackFunctions *cb, void *p)
{
    if (p == NULL)
        return;
    if (cb->freeMemory != NULL)
        cb->freeMemory(p);
    else
        free(p);
}

static void log_message(const Instance *inst, fmi2Status status, const char *format, ...)
    __attribute__((format(printf, 3, 4)));

static void log_message(const Instance *inst, fmi2Status status, const char *format, ...)
{
    if (status < fmi2Error && !inst->logging_on)
        return;
    char text[1024], escaped[2 * sizeof text];
    va_list args;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    /* the complete message as the logger's format, '%' doubled: hosts that do not format
     * (a ctypes callback cannot read variadic arguments) show it as it is */
    size_t n = 0;
    for (const char *c = text; *c != '\0'; c++) {
        if (*c == '%')
            escaped[n++] = '%';
        escaped[n++] = *c;
    }
    escaped[n] = '\0';
    const char *category = status >= fmi2Error ? "logStatusError" : status == fmi2Warning ? "logStatusWarning"
                                                                                           : "logAll";
    inst->callbacks.logger(inst->callbacks.componentEnvironment, inst->name, status, category, escaped);
}

/* ------------------------------------------------------------------ names and numbers */
/* The shortest text that reads back as exactly x, written as Python's repr writes floats
 * (so messages show a value as the user wrote it). */
static const char *shortest(double x, char *out, size_t size)
{
    for (int precision = 1; precision <= 17; precision++) {
        snprintf(out, size, "%.*g", precision, x);
        if (strtod(out, NULL) == x)
            break;
    }
    if (isfinite(x) && strpbrk(out, ".e") == NULL && strlen(out) + 3 <= size)
        strcat(out, ".0");
    return out;
}

static void variable_name(fmi2ValueReference vr, char *out, size_t size)
{
    if (vr < N_INPUTS)
        snprintf(out, size, "%s", INPUT_NAMES[vr]);
    else if (vr < VR_FIRST_PARAMETER + N_PARAMETERS)
        snprintf(out, size, "%s", PARAMETERS[vr - VR_FIRST_PARAMETER].name);
    else if (vr == VR_N_POINTS)
        snprintf(out, size, "n_points");
    else if (vr < VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS)
        snprintf(out, size, "%s", OUTPUTS[vr - VR_FIRST_OUTPUT].name);
    else if (vr < VR_FIRST_WEAR_DEPTH + N_POINTS)
        snprintf(out, size, "wear_depth[%u]", (unsigned)(vr - VR_FIRST_WEAR_DEPTH + 1));
    else
        snprintf(out, size, "<no variable with valueReference %u>", (unsigned)vr);
}

static void describe_non_finite_inputs(const Instance *inst, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < N_INPUTS && used < size; i++)
        if (inst->non_finite_inputs & (1u << i)) {
            int n = snprintf(out + used, size - used, "%s%s=%g", used ? ", " : "", INPUT_NAMES[i], inst->inputs[i]);
            if (n < 0)
                break;
            used += (size_t)n;
        }
}

/* ------------------------------------------------------------------ checks shared by the calls */
static int mode_is(const Instance *inst, const char *function, unsigned modes)
{
    static const char *const mode_names[] = {"instantiated", "initialization mode", "step complete", "terminated"};
    if (modes & (1u << inst->mode))
        return 1;
    log_message(inst, fmi2Error, "%s: not allowed in state %s (FMI 2.0 call sequence)", function,
                mode_names[inst->mode]);
    return 0;
}

#define M(mode) (1u << (mode))
#define ANY_MODE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_TERMINATED))

/* A valid instance and, for nvr > 0, non-NULL arrays; 0 (and a log where possible) otherwise. */
static int arrays_given(const Instance *inst, const char *function, size_t nvr, const void *vr, const void *value)
{
    if (inst == NULL)
        return 0;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        log_message(inst, fmi2Error, "%s: NULL value reference or value array for %zu variables", function, nvr);
        return 0;
    }
    return 1;
}

static int kernel_ok(const Instance *inst, const char *kernel, int32_t status)
{
    if (status == 0)
        return 1;
    log_message(inst, fmi2Error, "%s: the compiled kernel returned status %d", kernel, (int)status);
    return 0;
}

/* ------------------------------------------------------------------ parameters */
/* 1 if every parameter is allowed; else logs the first that is not (name, value, allowed range). */
static int parameters_valid(const Instance *inst, const double *values, const char *when)
{
    for (int i = 0; i < N_PARAMETERS; i++) {
        const ParameterInfo *p = &PARAMETERS[i];
        double x = values[i];
        int ok;
        if (p->n_choices > 0) {
            ok = x == floor(x) && x >= 0.0 && x < p->n_choices;
        } else {
            ok = isfinite(x);
            if (ok && p->has_low)
                ok = p->low_open ? x > p->low : x >= p->low;
            if (ok && p->has_high)
                ok = p->high_open ? x < p->high : x <= p->high;
            if (ok && p->above >= 0)
                ok = x > values[p->above];
        }
        if (!ok) {
            char text[32], other[32];
            if (p->n_choices > 0)   /* an Integer: its value as an integer */
                snprintf(text, sizeof text, "%.0f", x);
            else
                shortest(x, text, sizeof text);
            /* a rule with bounds says "> 0"; for a non-finite value say that it must be finite, too */
            const char *finite = p->n_choices == 0 && !isfinite(x) && (p->has_low || p->has_high || p->above >= 0)
                                     ? "a finite value "
                                     : "";
            if (p->above >= 0)
                log_message(inst, fmi2Error, "%s: parameter %s=%s is invalid: allowed %s%s (%s = %s)", when, p->name,
                            text, finite, p->allowed, PARAMETERS[p->above].name,
                            shortest(values[p->above], other, sizeof other));
            else
                log_message(inst, fmi2Error, "%s: parameter %s=%s is invalid: allowed %s%s", when, p->name, text,
                            finite, p->allowed);
            return 0;
        }
    }
    return 1;
}

/* The kernels' parameter vector from the FMU parameters (checked first); 1 on success. */
static int pack_parameters(Instance *inst, const char *when)
{
    if (!inst->parameters_changed)
        return 1;
    if (!parameters_valid(inst, inst->parameters, when))
        return 0;
    memset(inst->joint_parameters, 0, sizeof inst->joint_parameters);
    for (int i = 0; i < N_PARAMETERS; i++)
        inst->joint_parameters[PARAMETERS[i].slot] = inst->parameters[i];
    int32_t status = 0;
    if (!kernel_ok(inst, "wearjoint_complete_parameters",
                   wearjoint_complete_parameters(&status, NULL, inst->joint_parameters)))
        return 0;
    inst->parameters_changed = 0;
    inst->forces_stale = inst->wear_summary_stale = 1;
    return 1;
}

static void set_defaults(Instance *inst)
{
    inst->mode = MODE_INSTANTIATED;
    inst->time = 0.0;
    memset(inst->inputs, 0, sizeof inst->inputs);
    inst->non_finite_inputs = 0;
    for (int i = 0; i < N_PARAMETERS; i++)
        inst->parameters[i] = PARAMETERS[i].start;
    inst->parameters_changed = 1;
    inst->forces_stale = inst->wear_summary_stale = 1;
    memset(inst->memory, 0, sizeof inst->memory);
    memset(inst->result, 0, sizeof inst->result);
    memset(inst->wear_depth, 0, (size_t)inst->n_points * sizeof(double));
    memset(inst->block_min, 0, (size_t)inst->n_blocks * sizeof(double));
}

/* ------------------------------------------------------------------ the joint */
/* The joint's outputs for the current inputs (evaluated once per input change); ``output``
 * names the variable asked for, in messages. */
static int evaluate_forces(Instance *inst, const char *function, const char *output)
{
    if (!pack_parameters(inst, function))
        return 0;
    if (!inst->forces_stale)
        return 1;
    if (inst->non_finite_inputs) {
        char inputs[512];
        describe_non_finite_inputs(inst, inputs, sizeof inputs);
        log_message(inst, fmi2Error, "%s of %s: undefined for non-finite inputs (%s)", function, output, inputs);
        return 0;
    }
    int32_t status = 0;
    if (!kernel_ok(inst, "wearjoint_evaluate",
                   wearjoint_evaluate(&status, NULL, inst->inputs, inst->joint_parameters, inst->cos_phi,
                                      inst->sin_phi, inst->wear_depth, inst->block_min, inst->memory, inst->result,
                                      inst->mask, inst->n_points, inst->n_blocks)))
        return 0;
    inst->forces_stale = 0;
    return 1;
}

static int refresh_wear_summary(Instance *inst, const char *function)
{
    if (!pack_parameters(inst, function))
        return 0;
    if (!inst->wear_summary_stale)
        return 1;
    double largest = inst->wear_depth[0];
    for (int64_t k = 1; k < inst->n_points; k++)
        largest = inst->wear_depth[k] > largest ? inst->wear_depth[k] : largest;
    double volume = 0.0;
    if (!kernel_ok(inst, "wearjoint_worn_volume",
                   wearjoint_worn_volume(&volume, NULL, inst->joint_parameters, inst->wear_depth, inst->n_points)))
        return 0;
    inst->max_wear_depth = largest;
    inst->worn_volume = volume;
    inst->wear_summary_stale = 0;
    return 1;
}

/* ------------------------------------------------------------------ lifetime */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instance_name, fmi2Type fmu_type, fmi2String guid,
                              fmi2String resource_location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging_on)
{
    (void)resource_location;
    (void)visible;
    if (functions == NULL || functions->logger == NULL)
        return NULL; /* nowhere to report anything: the logger is mandatory in FMI 2.0 */
    const char *name = instance_name != NULL ? instance_name : "";
    const char *problem = NULL;
    if (instance_name == NULL || instance_name[0] == '\0')
        problem = "fmi2Instantiate: instanceName is missing";
    else if (fmu_type != fmi2CoSimulation)
        problem = "fmi2Instantiate: this FMU implements FMI 2.0 Co-Simulation only (fmuType must be fmi2CoSimulation)";
    else if (guid == NULL || strcmp(guid, MODEL_GUID) != 0)
        problem = "fmi2Instantiate: the GUID does not match this FMU's modelDescription.xml (" MODEL_GUID ")";
    if (problem != NULL) {
        functions->logger(functions->componentEnvironment, name, fmi2Error, "logStatusError", "%s", problem);
        return NULL;
    }
    Instance *inst = allocate(functions, 1, sizeof *inst);
    double *arrays = NULL;
    unsigned char *mask = NULL;
    char *copy = NULL;
    const int64_t n = N_POINTS, nb = (N_POINTS + BLOCK_SIZE - 1) / BLOCK_SIZE;
    if (inst != NULL) {
        arrays = allocate(functions, (size_t)(5 * n + nb), sizeof(double));
        mask = allocate(functions, (size_t)n, 1);
        copy = allocate(functions, strlen(name) + 1, 1);
    }
    if (inst == NULL || arrays == NULL || mask == NULL || copy == NULL) {
        functions->logger(functions->componentEnvironment, name, fmi2Error, "logStatusError", "%s",
                          "fmi2Instantiate: out of memory");
        if (inst != NULL) {
            release(functions, arrays);
            release(functions, mask);
            release(functions, copy);
            release(functions, inst);
        }
        return NULL;
    }
    memset(inst, 0, sizeof *inst);
    inst->callbacks = *functions;
    strcpy(copy, name);
    inst->name = copy;
    inst->logging_on = logging_on;
    inst->n_points = n;
    inst->n_blocks = nb;
    inst->phi = arrays;
    inst->cos_phi = arrays + n;
    inst->sin_phi = arrays + 2 * n;
    inst->wear_depth = arrays + 3 * n;
    inst->block_min = arrays + 4 * n;
    inst->mask = mask;
    memset(mask, 0, (size_t)n);
    int32_t status = 0;
    wearjoint_bushing_points(&status, NULL, inst->phi, inst->cos_phi, inst->sin_phi, n);
    set_defaults(inst);
    return inst;
}

void fmi2FreeInstance(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return;
    fmi2CallbackFunctions callbacks = inst->callbacks;
    release(&callbacks, inst->phi);
    release(&callbacks, inst->mask);
    release(&callbacks, inst->name);
    release(&callbacks, inst);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean logging_on, size_t n_categories,
                               const fmi2String categories[])
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    (void)categories;
    (void)n_categories;
    inst->logging_on = logging_on;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance,
                               fmi2Real start_time, fmi2Boolean stop_time_defined, fmi2Real stop_time)
{
    Instance *inst = c;
    (void)tolerance_defined;
    (void)tolerance;
    (void)stop_time_defined;
    (void)stop_time;
    if (inst == NULL || !mode_is(inst, "fmi2SetupExperiment", M(MODE_INSTANTIATED)))
        return fmi2Error;
    if (!isfinite(start_time)) {
        log_message(inst, fmi2Error, "fmi2SetupExperiment: startTime=%g is invalid: allowed a finite time", start_time);
        return fmi2Error;
    }
    inst->time = start_time;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2EnterInitializationMode", M(MODE_INSTANTIATED)))
        return fmi2Error;
    inst->mode = MODE_INITIALIZATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2ExitInitializationMode", M(MODE_INITIALIZATION)))
        return fmi2Error;
    if (!pack_parameters(inst, "fmi2ExitInitializationMode"))
        return fmi2Error;
    inst->mode = MODE_STEP_COMPLETE;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL || !mode_is(inst, "fmi2Terminate", M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE)))
        return fmi2Error;
    inst->mode = MODE_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    set_defaults(inst);
    return fmi2OK;
}

/* ------------------------------------------------------------------ values */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetReal", nvr, vr, value))
        return fmi2Error;
    if (!mode_is(inst, "fmi2GetReal", M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_TERMINATED)))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r < N_INPUTS) {
            value[i] = inst->inputs[r];
        } else if (r < VR_FIRST_PARAMETER + N_PARAMETERS && PARAMETERS[r - VR_FIRST_PARAMETER].n_choices == 0) {
            value[i] = inst->parameters[r - VR_FIRST_PARAMETER];
        } else if (r >= VR_FIRST_OUTPUT && r < VR_FIRST_OUTPUT + N_SCALAR_OUTPUTS) {
            const OutputInfo *o = &OUTPUTS[r - VR_FIRST_OUTPUT];
            if (o->source == OUTPUT_FROM_RESULT) {
                if (!evaluate_forces(inst, "fmi2GetReal", o->name))
                    return fmi2Error;
                value[i] = inst->result[o->index];
            } else {
                if (!refresh_wear_summary(inst, "fmi2GetReal"))
                    return fmi2Error;
                value[i] = o->source == OUTPUT_MAX_WEAR_DEPTH ? inst->max_wear_depth : inst->worn_volume;
            }
        } else if (r >= VR_FIRST_WEAR_DEPTH && r < VR_FIRST_WEAR_DEPTH + N_POINTS) {
            value[i] = inst->wear_depth[r - VR_FIRST_WEAR_DEPTH];
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            log_message(inst, fmi2Error, "fmi2GetReal: %s is not a Real variable", name);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

/* A parameter may be set before exitInitializationMode only. */
static int parameter_settable(const Instance *inst, const char *function, fmi2ValueReference vr)
{
    if (inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION)
        return 1;
    log_message(inst, fmi2Error, "%s: parameter %s is fixed: set it before fmi2ExitInitializationMode", function,
                PARAMETERS[vr - VR_FIRST_PARAMETER].name);
    return 0;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetReal", nvr, vr, value))
        return fmi2Error;
    if (!mode_is(inst, "fmi2SetReal", M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE)))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r < N_INPUTS) {
            inst->inputs[r] = value[i];
            if (isfinite(value[i]))
                inst->non_finite_inputs &= ~(1u << r);
            else
                inst->non_finite_inputs |= 1u << r;
            inst->forces_stale = 1;
        } else if (r < VR_FIRST_PARAMETER + N_PARAMETERS && PARAMETERS[r - VR_FIRST_PARAMETER].n_choices == 0) {
            if (!parameter_settable(inst, "fmi2SetReal", r))
                return fmi2Error;
            inst->parameters[r - VR_FIRST_PARAMETER] = value[i];
            inst->parameters_changed = 1;
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            log_message(inst, fmi2Error, "fmi2SetReal: variable %s cannot be set", name);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetInteger", nvr, vr, value))
        return fmi2Error;
    if (!mode_is(inst, "fmi2GetInteger", M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_TERMINATED)))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r == VR_N_POINTS) {
            value[i] = (fmi2Integer)inst->n_points;
        } else if (r >= VR_FIRST_PARAMETER && r < VR_FIRST_PARAMETER + N_PARAMETERS &&
                   PARAMETERS[r - VR_FIRST_PARAMETER].n_choices > 0) {
            value[i] = (fmi2Integer)inst->parameters[r - VR_FIRST_PARAMETER];
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            log_message(inst, fmi2Error, "fmi2GetInteger: %s is not an Integer variable", name);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetInteger", nvr, vr, value))
        return fmi2Error;
    if (!mode_is(inst, "fmi2SetInteger", M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE)))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r == VR_N_POINTS) {
            if (value[i] != inst->n_points) {
                log_message(inst, fmi2Error,
                            "fmi2SetInteger: n_points is fixed at %lld when the FMU is built; rebuild it for %d "
                            "points (wearjoint build-fmu --n-points %d)",
                            (long long)inst->n_points, (int)value[i], (int)value[i]);
                return fmi2Error;
            }
        } else if (r >= VR_FIRST_PARAMETER && r < VR_FIRST_PARAMETER + N_PARAMETERS &&
                   PARAMETERS[r - VR_FIRST_PARAMETER].n_choices > 0) {
            if (!parameter_settable(inst, "fmi2SetInteger", r))
                return fmi2Error;
            inst->parameters[r - VR_FIRST_PARAMETER] = value[i];
            inst->parameters_changed = 1;
        } else {
            char name[96];
            variable_name(r, name, sizeof name);
            log_message(inst, fmi2Error, "fmi2SetInteger: variable %s cannot be set", name);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

#define NO_VARIABLES_OF_TYPE(function, type, qualifier)                                                     \
    fmi2Status function(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, qualifier type value[])  \
    {                                                                                                       \
        Instance *inst = c;                                                                                 \
        if (!arrays_given(inst, #function, nvr, vr, value))                                                 \
            return fmi2Error;                                                                               \
        if (nvr == 0)                                                                                       \
            return fmi2OK;                                                                                  \
        log_message(inst, fmi2Error, "%s: this FMU has no %s variables (valueReference %u)", #function, #type, \
                    (unsigned)vr[0]);                                                                       \
        return fmi2Error;                                                                                   \
    }

NO_VARIABLES_OF_TYPE(fmi2GetBoolean, fmi2Boolean, )
NO_VARIABLES_OF_TYPE(fmi2SetBoolean, fmi2Boolean, const)
NO_VARIABLES_OF_TYPE(fmi2GetString, fmi2String, )
NO_VARIABLES_OF_TYPE(fmi2SetString, fmi2String, const)

/* ------------------------------------------------------------------ stepping */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real current_time, fmi2Real step_size, fmi2Boolean no_set_state_before)
{
    Instance *inst = c;
    (void)no_set_state_before;
    if (inst == NULL || !mode_is(inst, "fmi2DoStep", M(MODE_STEP_COMPLETE)))
        return fmi2Error;
    if (inst->non_finite_inputs) {
        char inputs[512];
        describe_non_finite_inputs(inst, inputs, sizeof inputs);
        log_message(inst, fmi2Error, "fmi2DoStep: doStep at t=%.17g s rejected: non-finite inputs (%s)", current_time, inputs);
        return fmi2Discard;
    }
    if (!(step_size >= 0.0 && isfinite(step_size)) || !isfinite(current_time)) {
        log_message(inst, fmi2Error, "fmi2DoStep: doStep rejected: step size %g s at t=%g s is not a finite value >= 0",
                    step_size, current_time);
        return fmi2Discard;
    }
    /* the forces read since the inputs changed are the evaluation the step accepts: no second one */
    int32_t changed = 0;
    int32_t status = inst->forces_stale
                         ? wearjoint_advance(&changed, NULL, inst->inputs, inst->joint_parameters, inst->cos_phi,
                                             inst->sin_phi, inst->wear_depth, inst->block_min, inst->memory,
                                             inst->result, inst->mask, inst->n_points, inst->n_blocks, step_size)
                         : wearjoint_accept(&changed, NULL, inst->inputs, inst->joint_parameters, inst->cos_phi,
                                            inst->sin_phi, inst->wear_depth, inst->block_min, inst->memory,
                                            inst->result, inst->mask, inst->n_points, inst->n_blocks, step_size);
    if (!kernel_ok(inst, "wearjoint_advance", status))
        return fmi2Error;
    if (changed)
        inst->wear_summary_stale = 1;
    inst->forces_stale = 1;
    inst->time = current_time + step_size;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    log_message(inst, fmi2Error, "fmi2CancelStep: doStep always completes synchronously here");
    return fmi2Error;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Status *value)
{
    Instance *inst = c;
    (void)kind;
    (void)value;
    if (inst == NULL)
        return fmi2Error;
    log_message(inst, fmi2Error, "fmi2GetStatus: doStep never returns fmi2Pending here");
    return fmi2Error;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value)
{
    Instance *inst = c;
    if (inst == NULL || value == NULL)
        return fmi2Error;
    if (kind != fmi2LastSuccessfulTime) {
        log_message(inst, fmi2Error, "fmi2GetRealStatus: only fmi2LastSuccessfulTime is available");
        return fmi2Error;
    }
    *value = inst->time;
    return fmi2OK;
}

#define NO_STATUS_OF_TYPE(function, type)                                                         \
    fmi2Status function(fmi2Component c, const fmi2StatusKind kind, type *value)                 \
    {                                                                                             \
        Instance *inst = c;                                                                       \
        (void)kind;                                                                               \
        (void)value;                                                                              \
        if (inst == NULL)                                                                         \
            return fmi2Error;                                                                     \
        log_message(inst, fmi2Error, "%s: doStep never returns fmi2Pending here", #function);    \
        return fmi2Error;                                                                         \
    }

NO_STATUS_OF_TYPE(fmi2GetIntegerStatus, fmi2Integer)
NO_STATUS_OF_TYPE(fmi2GetBooleanStatus, fmi2Boolean)
NO_STATUS_OF_TYPE(fmi2GetStringStatus, fmi2String)

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    Instance *inst = c;
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    if (inst == NULL)
        return fmi2Error;
    log_message(inst, fmi2Error, "fmi2SetRealInputDerivatives: canInterpolateInputs is false for this FMU");
    return fmi2Error;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    Instance *inst = c;
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    if (inst == NULL)
        return fmi2Error;
    log_message(inst, fmi2Error, "fmi2GetRealOutputDerivatives: maxOutputDerivativeOrder is 0 for this FMU");
    return fmi2Error;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[], size_t n_unknown,
                                        const fmi2ValueReference known[], size_t n_known, const fmi2Real dv_known[],
                                        fmi2Real dv_unknown[])
{
    Instance *inst = c;
    (void)unknown;
    (void)n_unknown;
    (void)known;
    (void)n_known;
    (void)dv_known;
    (void)dv_unknown;
    if (inst == NULL)
        return fmi2Error;
    log_message(inst, fmi2Error, "fmi2GetDirectionalDerivative: providesDirectionalDerivative is false for this FMU");
    return fmi2Error;
}

/* ------------------------------------------------------------------ FMU state */
static size_t state_size(const Instance *inst) { return STATE_DOUBLES(inst->n_points) * sizeof(double); }

static FmuState *new_state(const Instance *inst)
{
    FmuState *s = allocate(&inst->callbacks, 1, sizeof *s + state_size(inst));
    if (s == NULL)
        log_message(inst, fmi2Error, "FMU state: out of memory");
    else
        s->size = state_size(inst);
    return s;
}

static void write_state(const Instance *inst, FmuState *s)
{
    double *d = (double *)s->bytes;
    memcpy(d, STATE_MAGIC, 8);
    d[1] = inst->time;
    d[2] = inst->mode == MODE_STEP_COMPLETE || inst->mode == MODE_TERMINATED ? 1.0 : 0.0;
    d += STATE_HEAD_DOUBLES;
    memcpy(d, inst->inputs, sizeof inst->inputs);
    memcpy(d + N_INPUTS, inst->parameters, sizeof inst->parameters);
    memcpy(d + N_INPUTS + N_PARAMETERS, inst->memory, sizeof inst->memory);
    memcpy(d + N_INPUTS + N_PARAMETERS + N_MEMORY, inst->wear_depth, (size_t)inst->n_points * sizeof(double));
}

/* 1 if ``bytes`` is a valid state of this FMU (size, magic, finite wear >= 0, valid parameters). */
static int state_valid(const Instance *inst, const unsigned char *bytes, size_t size, const char *function)
{
    if (size != state_size(inst) || memcmp(bytes, STATE_MAGIC, 8) != 0) {
        log_message(inst, fmi2Error, "%s: not a ClearanceWearJoint state for n_points=%lld (%zu bytes)", function,
                    (long long)inst->n_points, size);
        return 0;
    }
    const double *d = (const double *)bytes;
    if (!isfinite(d[1]) || (d[2] != 0.0 && d[2] != 1.0)) {
        log_message(inst, fmi2Error, "%s: the state's time or initialised flag is invalid", function);
        return 0;
    }
    d += STATE_HEAD_DOUBLES;
    if (!parameters_valid(inst, d + N_INPUTS, function))
        return 0;
    const double *wear = d + N_INPUTS + N_PARAMETERS + N_MEMORY;
    for (int64_t k = 0; k < inst->n_points; k++)
        if (!(wear[k] >= 0.0 && isfinite(wear[k]))) {
            log_message(inst, fmi2Error, "%s: the state's wear depths must be finite and >= 0 (wear_depth[%lld]=%g)",
                        function, (long long)k + 1, wear[k]);
            return 0;
        }
    return 1;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (state == NULL) {
        log_message(inst, fmi2Error, "fmi2GetFMUstate: NULL state pointer");
        return fmi2Error;
    }
    FmuState *s = *state;
    if (s == NULL) {
        if ((s = new_state(inst)) == NULL)
            return fmi2Error;
        *state = s;
    } else if (s->size != state_size(inst)) {
        log_message(inst, fmi2Error, "fmi2GetFMUstate: the state given to overwrite is not of this FMU");
        return fmi2Error;
    }
    write_state(inst, s);
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const FmuState *s = state;
    if (s == NULL || s->size != state_size(inst)) {
        log_message(inst, fmi2Error, "fmi2SetFMUstate: NULL or not a state of this FMU");
        return fmi2Error;
    }
    const double *d = (const double *)s->bytes;
    inst->time = d[1];
    if (d[2] == 1.0)
        inst->mode = MODE_STEP_COMPLETE;
    else if (inst->mode == MODE_STEP_COMPLETE || inst->mode == MODE_TERMINATED)
        inst->mode = MODE_INITIALIZATION;
    d += STATE_HEAD_DOUBLES;
    memcpy(inst->inputs, d, sizeof inst->inputs);
    inst->non_finite_inputs = 0;
    for (int i = 0; i < N_INPUTS; i++)
        if (!isfinite(inst->inputs[i]))
            inst->non_finite_inputs |= 1u << i;
    if (memcmp(inst->parameters, d + N_INPUTS, sizeof inst->parameters) != 0) {
        memcpy(inst->parameters, d + N_INPUTS, sizeof inst->parameters);
        inst->parameters_changed = 1;
    }
    memcpy(inst->memory, d + N_INPUTS + N_PARAMETERS, sizeof inst->memory);
    memcpy(inst->wear_depth, d + N_INPUTS + N_PARAMETERS + N_MEMORY, (size_t)inst->n_points * sizeof(double));
    int32_t status = 0;
    wearjoint_block_minima(&status, NULL, inst->wear_depth, inst->block_min, inst->n_points, inst->n_blocks);
    inst->forces_stale = inst->wear_summary_stale = 1;
    return pack_parameters(inst, "fmi2SetFMUstate") ? fmi2OK : fmi2Error;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (state == NULL) {
        log_message(inst, fmi2Error, "fmi2FreeFMUstate: NULL state pointer");
        return fmi2Error;
    }
    release(&inst->callbacks, *state);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const FmuState *s = state;
    if (s == NULL || size == NULL) {
        log_message(inst, fmi2Error, "fmi2SerializedFMUstateSize: NULL state or size pointer");
        return fmi2Error;
    }
    *size = s->size;
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    const FmuState *s = state;
    if (s == NULL || bytes == NULL || size < s->size) {
        log_message(inst, fmi2Error, "fmi2SerializeFMUstate: NULL state or buffer, or a buffer of %zu bytes for a "
                    "state of %zu", size, s != NULL ? s->size : (size_t)0);
        return fmi2Error;
    }
    memcpy(bytes, s->bytes, s->size);
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state)
{
    Instance *inst = c;
    if (inst == NULL)
        return fmi2Error;
    if (bytes == NULL || state == NULL) {
        log_message(inst, fmi2Error, "fmi2DeSerializeFMUstate: NULL bytes or state pointer");
        return fmi2Error;
    }
    if (!state_valid(inst, (const unsigned char *)bytes, size, "fmi2DeSerializeFMUstate"))
        return fmi2Error;
    FmuState *s = *state;
    if (s != NULL && s->size != size) {
        log_message(inst, fmi2Error, "fmi2DeSerializeFMUstate: the state given to overwrite is not of this FMU");
        return fmi2Error;
    }
    if (s == NULL && (s = new_state(inst)) == NULL)
        return fmi2Error;
    memcpy(s->bytes, bytes, size);
    *state = s;
    return fmi2OK;
}
