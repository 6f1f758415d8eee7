/* ClearanceWearJoint as a model of the generic FMI layers (fmu_model.h), in three files by concern on the
 * joint's data (struct FmuModel, joint_model.h): this one owns the joint's memory and data (inputs,
 * parameters, the kernels' arrays), checks parameters against the generated table and calls the compiled
 * kernels (joint_kernels.h): lifetime, evaluation, steps (Co-Simulation) and Model Exchange;
 * joint_variables.c maps the variables by value reference; joint_state.c is the FMU state and its size.
 *
 * Semantics (docs/reference/fmu.md §5): the forces are direct feed-through, evaluated at the first read of a joint
 * output after an input changed; Co-Simulation accepts a step with the inputs held at its start (wear, contact
 * onsets); Model Exchange has no continuous states and one event indicator, the signed penetration (a contact onset
 * is a state event, where the approach velocity is stored), and applies wear at each completed integrator step. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "joint_model.h"
#include "joint_kernels.h"

/* Model Exchange: a time this share of the last completed step's end (of 1 ms at least) before it is that end */
#define TIME_ROUNDING 1e-12

static int kernel_ok(const FmuModel *model, const char *kernel, int32_t status)
{
    if (status == 0)
        return 1;
    fmu_log(&model->host, FMU_ERROR, "%s", kernel);
    return 0;
}

/* ------------------------------------------------------------------ lifetime */
static int allocate_arrays(FmuModel *model, int64_t n_points)
{
    int64_t n_blocks = (n_points + BLOCK_SIZE - 1) / BLOCK_SIZE;
    double *arrays = model->host.allocate(model->host.environment, (size_t)(7 * n_points + n_blocks), sizeof(double));
    unsigned char *mask = model->host.allocate(model->host.environment, (size_t)n_points, 1);
    if (arrays == NULL || mask == NULL) {
        if (arrays != NULL)
            model->host.release(model->host.environment, arrays);
        if (mask != NULL)
            model->host.release(model->host.environment, mask);
        fmu_log(&model->host, FMU_ERROR, "out of memory for %lld bushing points", (long long)n_points);
        return 0;
    }
    if (model->phi != NULL)
        model->host.release(model->host.environment, model->phi);
    if (model->mask != NULL)
        model->host.release(model->host.environment, model->mask);
    model->n_points = n_points;
    model->n_blocks = n_blocks;
    model->phi = arrays;
    model->cos_phi = arrays + n_points;
    model->sin_phi = arrays + 2 * n_points;
    model->wear_depth = arrays + 3 * n_points;
    model->work = arrays + 4 * n_points;
    model->block_min = arrays + 6 * n_points;     /* work: 2 n_points */
    model->mask = mask;
    int32_t status = 0;
    wearjoint_bushing_points(&status, NULL, model->phi, model->cos_phi, model->sin_phi, n_points);
    return 1;
}

/* Default inputs and parameters, an unworn bushing, no contact memory (n_points as it is). */
static void reset(FmuModel *model)
{
    model->time = model->last_accepted_time = 0.0;
    memset(model->inputs, 0, sizeof model->inputs);
    model->non_finite_inputs = 0;
    for (int i = 0; i < N_PARAMETERS; i++)
        model->parameters[i] = PARAMETERS[i].start;
    model->parameters_changed = 1;
    model->forces_stale = model->wear_summary_stale = model->jacobian_stale = 1;
    model->onsets_accepted = model->warned_wear_step = model->started = model->jacobian_read = 0;
    model->jacobian_unchecked = 0;
    memset(model->memory, 0, sizeof model->memory);
    model->memory[M_START_FORCE] = NO_START_FORCE;
    memset(model->result, 0, sizeof model->result);
    memset(model->wear_depth, 0, (size_t)model->n_points * sizeof(double));
    memset(model->block_min, 0, (size_t)model->n_blocks * sizeof(double));
}

int joint_resize(FmuModel *model, int64_t n_points)
{
    if (n_points != model->n_points && !allocate_arrays(model, n_points))
        return 0;
    reset(model);
    return 1;
}

void model_free(FmuModel *model)
{
    if (model == NULL)
        return;
    if (model->phi != NULL)
        model->host.release(model->host.environment, model->phi);
    if (model->mask != NULL)
        model->host.release(model->host.environment, model->mask);
    fmu_free_instance(model);
}

/* N_POINTS bushing points and the start values. */
FmuModel *model_new(const char *name, int logging_on, FmuLogFunction *log, FmuAllocateFunction *allocate,
                    FmuReleaseFunction *release, void *environment)
{
    FmuModel *model = fmu_new_instance(sizeof *model, name, logging_on, log, allocate, release, environment);
    if (model == NULL)
        return NULL;
    if (!allocate_arrays(model, N_POINTS)) {
        model_free(model);
        return NULL;
    }
    reset(model);
    model->configured_n_points = N_POINTS;
    return model;
}

FmuHost *model_host(FmuModel *model) { return &model->host; }

/* Back to the start values, n_points (FMI 3.0) too. */
int model_reset(FmuModel *model)
{
    if (!joint_resize(model, N_POINTS))
        return 0;
    model->configured_n_points = N_POINTS;
    return 1;
}

double model_time(const FmuModel *model) { return model->time; }

void model_set_start_time(FmuModel *model, double time)
{
    model->time = model->last_accepted_time = time;
}

int model_exit_initialization(FmuModel *model, const char *function)
{
    if (!joint_pack_parameters(model, function))
        return 0;
    model->last_accepted_time = model->time;
    return 1;
}

/* ------------------------------------------------------------------ inputs and parameters */
void joint_set_input(FmuModel *model, int index, double value)
{
    if (!(value == model->inputs[index]))
        model->onsets_accepted = 0;
    model->inputs[index] = value;
    if (isfinite(value))
        model->non_finite_inputs &= ~(1u << index);
    else
        model->non_finite_inputs |= 1u << index;
    model->forces_stale = 1;
}

void joint_set_parameter(FmuModel *model, int index, double value)
{
    model->parameters[index] = value;
    model->parameters_changed = 1;
}

int joint_pack_parameters(FmuModel *model, const char *when)
{
    if (!model->parameters_changed)
        return 1;
    if (!fmu_parameters_valid(&model->host, PARAMETERS, N_PARAMETERS, model->parameters, when))
        return 0;
    memset(model->joint_parameters, 0, sizeof model->joint_parameters);
    for (int i = 0; i < N_PARAMETERS; i++)
        model->joint_parameters[PARAMETERS[i].slot] = model->parameters[i];
    int32_t status = 0;
    if (!kernel_ok(model, "wearjoint_complete_parameters failed",
                   wearjoint_complete_parameters(&status, NULL, model->joint_parameters)))
        return 0;
    model->parameters_changed = 0;
    model->forces_stale = model->wear_summary_stale = 1;
    return 1;
}

/* ------------------------------------------------------------------ the kernels */
static int all_finite(const double *values, int n)
{
    /* on the bits: a value's exponent field plus one carries into bit 63 iff it is all ones (infinite or NaN); the
     * values are independent (a sum of values * 0 is one dependent chain of additions, 4 cycles each) */
    const uint64_t exponent = 0x7ff0000000000000u, exponent_one = 0x0010000000000000u;
    uint64_t carries = 0;
    for (int i = 0; i < n; i++) {
        uint64_t bits;
        memcpy(&bits, &values[i], sizeof bits);
        carries |= (bits & exponent) + exponent_one;
    }
    return !(carries >> 63);
}

/* 1 if the n values per result slot of ``values`` (the result: 1, the jacobian: N_INPUTS) are finite for every
 * output read from the result; else logs the first that is not. */
static int outputs_finite(const FmuModel *model, const double *values, int n, const char *what,
                          const char *function, const char *output)
{
    if (all_finite(values, N_RESULT * n))   /* else look for the output that is not */
        return 1;
    for (int i = 0; i < N_SCALAR_OUTPUTS; i++) {   /* finite inputs so large that the geometry overflows */
        for (int m = 0; m < n && OUTPUTS[i].source == OUTPUT_FROM_RESULT; m++) {
            double value = values[OUTPUTS[i].index * n + m];
            if (isfinite(value))
                continue;
            double largest = 0.0;
            for (int k = 0; k < N_INPUTS; k++)
                largest = fabs(model->inputs[k]) > largest ? fabs(model->inputs[k]) : largest;
            fmu_log(&model->host, FMU_ERROR, "%s of %s: %s %s=%g is not finite for inputs up to |%g| and the "
                    "body offsets set: allowed inputs and offsets whose contact geometry stays finite", function,
                    output, what, OUTPUTS[i].name, value, largest);
            return 0;
        }
    }
    return 1;
}

int joint_evaluate(FmuModel *model, const char *function, const char *output)
{
    if (!model->forces_stale && !model->parameters_changed)
        return 1;
    if (!joint_pack_parameters(model, function))
        return 0;
    if (!model->forces_stale)
        return 1;
    if (model->non_finite_inputs) {
        char inputs[512];
        describe_non_finite_inputs(model, inputs, sizeof inputs);
        fmu_log(&model->host, FMU_ERROR, "%s of %s: undefined for non-finite inputs (%s)", function, output, inputs);
        return 0;
    }
    int32_t status = 0;
    /* a host that read the last evaluation's derivatives (a linearising master) reads these too: one pass for both
     * (the same forces: the kernels' sums do not depend on whether they also take the derivatives) */
    int with_jacobian = model->jacobian_read;
    model->jacobian_read = 0;
    if (with_jacobian) {
        if (!kernel_ok(model, "wearjoint_jacobian failed",
                       wearjoint_jacobian(&status, NULL, model->inputs, model->joint_parameters, model->cos_phi,
                                          model->sin_phi, model->wear_depth, model->block_min, model->memory,
                                          model->result, model->jacobian, model->n_points, model->n_blocks)))
            return 0;
    } else if (!kernel_ok(model, "wearjoint_evaluate failed",
                          wearjoint_evaluate(&status, NULL, model->inputs, model->joint_parameters, model->cos_phi,
                                             model->sin_phi, model->wear_depth, model->block_min, model->memory,
                                             model->result, model->mask, model->n_points, model->n_blocks))) {
        return 0;
    }
    if (!outputs_finite(model, model->result, 1, "output", function, output))
        return 0;
    model->forces_stale = 0;
    model->jacobian_stale = !with_jacobian;
    model->jacobian_unchecked = with_jacobian;   /* a reader checks the values it reads (joint_variables.c) */
    return 1;
}

/* The derivatives at the evaluation in result (the same kernels, the same evaluation written to scratch). */
int joint_jacobian(FmuModel *model, const char *function, const char *output)
{
    if (!joint_evaluate(model, function, output))
        return 0;
    if (!model->jacobian_stale) {
        if (model->jacobian_unchecked &&
            !outputs_finite(model, model->jacobian, N_INPUTS, "the derivative of output", function, output))
            return 0;
        model->jacobian_unchecked = 0;
        model->jacobian_read = 1;
        return 1;
    }
    double result[N_RESULT];
    memcpy(result, model->result, sizeof result);   /* its deepest point seeds the search */
    int32_t status = 0;
    if (!kernel_ok(model, "wearjoint_jacobian failed",
                   wearjoint_jacobian(&status, NULL, model->inputs, model->joint_parameters, model->cos_phi,
                                      model->sin_phi, model->wear_depth, model->block_min, model->memory, result,
                                      model->jacobian, model->n_points, model->n_blocks)))
        return 0;
    if (!outputs_finite(model, model->jacobian, N_INPUTS, "the derivative of output", function, output))
        return 0;
    model->jacobian_stale = model->jacobian_unchecked = 0;
    model->jacobian_read = 1;
    return 1;
}

int joint_wear_summary(FmuModel *model, const char *function)
{
    if (!joint_pack_parameters(model, function))
        return 0;
    if (!model->wear_summary_stale)
        return 1;
    double largest = model->wear_depth[0];
    for (int64_t k = 1; k < model->n_points; k++)
        largest = model->wear_depth[k] > largest ? model->wear_depth[k] : largest;
    double volume = 0.0;
    if (!kernel_ok(model, "wearjoint_worn_volume failed",
                   wearjoint_worn_volume(&volume, NULL, model->joint_parameters, model->wear_depth, model->n_points)))
        return 0;
    model->max_wear_depth = largest;
    model->worn_volume = volume;
    model->wear_summary_stale = 0;
    return 1;
}

/* The warnings of an accepted step (accept_step), from the kernels' result at its start. */
static int step_warnings(FmuModel *model, double dt, int32_t changed, const char *function)
{
    int status = FMU_OK;
    const double *p = model->joint_parameters;
    if (!model->started) {
        model->started = 1;
        double e = hypot(model->result[R_ECCENTRICITY_X], model->result[R_ECCENTRICITY_Y]);
        double radius = p[P_BUSHING_RADIUS];
        if (e > radius) {
            fmu_log_returned_warning(&model->host, "%s: at t=%.17g s the inputs put the pin centre %g m from the "
                    "bushing centre, outside the bushing (radius %g m): the contact force is meaningless.  The "
                    "inputs are the bodies' reference points; are the offsets set (pin_offset_x=%g, pin_offset_y=%g, "
                    "bushing_offset_x=%g, bushing_offset_y=%g m, each in its body's frame)?", function, model->time,
                    e, radius, p[P_PIN_OFFSET_X], p[P_PIN_OFFSET_Y], p[P_BUSHING_OFFSET_X], p[P_BUSHING_OFFSET_Y]);
            status = FMU_WARNING;
        } else {
            double bounds[3] = {0.0, 0.0, 0.0};   /* the pin's overlap, the admissible penetration [m] and force [N] */
            int32_t inadmissible = 0;
            wearjoint_wall_overlap(&inadmissible, NULL, model->result, model->joint_parameters, model->wear_depth,
                                   model->n_points, bounds);
            if (inadmissible) {
                fmu_log_returned_warning(&model->host, "%s: at t=%.17g s the inputs put the pin %g m into the bushing "
                        "wall (admissible %g m) with a normal force of %g N (admissible %g N): this first step is "
                        "taken, as a master may step once on start values, but wears nothing and starts no contact; "
                        "a later step there is discarded (the bodies' offsets, the wiring? docs/reference/model.md "
                        "§3.14)", function, model->time, bounds[0], bounds[1], model->result[R_NORMAL_FORCE],
                        bounds[2]);
                status = FMU_WARNING;
            }
        }
    }
    if (changed == STEP_OVERSHOT && !model->warned_wear_step) {
        model->warned_wear_step = 1;
        fmu_log(&model->host, FMU_WARNING, "%s: at t=%.17g s a wearing step of %g s is over the wear-step limit "
                "(at most %g s, and a share k_f k_w v dt of at most %g of a conforming contact's penetration, %g "
                "with the explicit wear placements): the step no longer resolves the wear; take shorter steps or a "
                "smaller wear_factor (docs/reference/model.md §7; said once)", function, model->time, dt, MAX_WEAR_STEP_S,
                WEAR_STEP_SHARE, WEAR_STEP_SHARE_EXPLICIT);
        /* logged as a warning, returned fmi2OK: some masters (OMSimulator) end the run on a warning status */
    }
    return status;
}

/* Accept a step of dt [s] at the current inputs: wear and contact-onset bookkeeping; held != 0: the inputs were held
 * over the step (Co-Simulation: the wear takes their force), else they end it (Model Exchange: the step's mean force,
 * docs/reference/model.md §3.11).  FMU_DISCARD (logged, state unchanged) for non-finite inputs or dt, for inputs
 * deeper in the bushing wall than any contact or a bushing worn through (Co-Simulation; Model Exchange: FMU_ERROR;
 * docs/reference/model.md §3.14).  FMU_WARNING (logged, the step accepted), once per instance: the first step's pin
 * centre lies outside the bushing (the inputs likely lack the offsets), or deeper in its wall than any contact.  A
 * wearing step over the wear-step limit (docs/reference/model.md §7) is logged as a warning once per instance and
 * returns FMU_OK: the run goes on. */
static int accept_step(FmuModel *model, double dt, int held, const char *function)
{
    if (model->non_finite_inputs) {
        char inputs[512];
        describe_non_finite_inputs(model, inputs, sizeof inputs);
        fmu_log(&model->host, FMU_ERROR, "%s: step at t=%.17g s rejected: non-finite inputs (%s)", function,
                model->time, inputs);
        return FMU_DISCARD;
    }
    if (!(dt >= 0.0 && isfinite(dt))) {
        fmu_log(&model->host, FMU_ERROR, "%s: step rejected: step size %g s is not a finite value >= 0", function, dt);
        return FMU_DISCARD;
    }
    if (!joint_pack_parameters(model, function))
        return FMU_ERROR;
    /* the forces read since the inputs changed are the step's evaluation; derivatives read there: a linearising host,
     * as one that read them before it set these inputs (one step late: libcosim, fmpy's SSP master), whose loads and
     * derivatives are evaluated here, in one pass, and still read (its next reading takes both) */
    int late = held && model->forces_stale && model->jacobian_read;
    if (late && !joint_evaluate(model, function, "the step's loads"))
        return FMU_ERROR;
    model->jacobian_read |= late;
    int linearising = held && !model->forces_stale && !model->jacobian_stale && model->jacobian_read;
    int32_t changed = 0;
    int32_t status = model->forces_stale
                         ? wearjoint_advance(&changed, NULL, model->inputs, model->joint_parameters, model->cos_phi,
                                             model->sin_phi, model->wear_depth, model->block_min, model->memory,
                                             model->result, model->mask, model->work, model->n_points,
                                             model->n_blocks, dt, held)
                         : wearjoint_accept(&changed, NULL, model->inputs, model->joint_parameters, model->cos_phi,
                                            model->sin_phi, model->wear_depth, model->block_min, model->memory,
                                            model->result, model->jacobian, model->mask, model->work,
                                            model->n_points, model->n_blocks, dt, linearising ? HELD_LINEARISED : held);
    if (!kernel_ok(model, "wearjoint_advance failed", status))
        return FMU_ERROR;
    double radius = model->parameters[STATE_PARAMETER_BUSHING_RADIUS];
    if (changed == STEP_INADMISSIBLE) {   /* deeper in the wall than any contact, or worn through: nothing changed */
        double bounds[3] = {0.0, 0.0, 0.0};   /* the pin's overlap, the admissible penetration [m] and force [N] */
        int32_t ignored = 0;
        wearjoint_wall_overlap(&ignored, NULL, model->result, model->joint_parameters, model->wear_depth,
                               model->n_points, bounds);
        if (joint_wear_summary(model, function) && !(model->max_wear_depth <= radius))
            fmu_log(&model->host, FMU_ERROR, "%s: step at t=%.17g s rejected: the bushing wore through before it: "
                    "max depth %g m, its radius %g m: nothing changed (docs/reference/model.md §3.14)", function,
                    model->time, model->max_wear_depth, radius);
        else fmu_log(&model->host, FMU_ERROR, "%s: step at t=%.17g s rejected: the inputs put the pin %g m into the "
                "bushing wall (along its eccentricity; admissible %g m, " ADMISSIBLE_SHARE_TEXT " the pin radius) "
                "with a normal force of %g N (admissible %g N): no contact of this joint reaches it, nothing changed; "
                "the %s step is too long for the contact, or the inputs are wrong (the bodies' offsets, the wiring; "
                "docs/reference/model.md §3.14)", function, model->time, bounds[0], bounds[1],
                model->result[R_NORMAL_FORCE], bounds[2], held ? "communication" : "integrator's");
        return held ? FMU_DISCARD : FMU_ERROR;
    }
    if (changed < 0) {   /* the kernels refused the step's wear (absurd or not finite): nothing changed */
        fmu_log(&model->host, FMU_ERROR, "%s: step rejected: a step of %g s wears the bushing by more than its "
                "radius %g m (or by a non-finite depth)", function, dt, radius);
        return FMU_DISCARD;
    }
    if (changed)
        model->wear_summary_stale = 1;
    model->forces_stale = 1;
    model->onsets_accepted = 1;
    return step_warnings(model, dt, changed, function);
}

/* ------------------------------------------------------------------ Co-Simulation */
/* Accept the step with the inputs held at t: wear and contact-onset bookkeeping. */
int model_do_step(FmuModel *model, double t, double h, const char *function)
{
    double previous = model->time;
    model->time = t;
    int status = accept_step(model, h, 1, function);
    if (status > FMU_WARNING) {
        model->time = previous;
        return status;
    }
    model->time = model->last_accepted_time = t + h;
    return status;   /* a warning: the step is accepted */
}

/* ------------------------------------------------------------------ Model Exchange: no continuous states */
/* The time (finite; 0, logged, otherwise). */
int model_set_time(FmuModel *model, double time, const char *function)
{
    if (!isfinite(time)) {
        fmu_log(&model->host, FMU_ERROR, "%s: time=%g is not finite", function, time);
        return 0;
    }
    model->time = time;
    return 1;
}

/* none to get, set or differentiate */
int model_get_continuous_states(FmuModel *model, double *x, const char *function)
{ return (void)model, (void)x, (void)function, 1; }
int model_set_continuous_states(FmuModel *model, const double *x, const char *function)
{ return (void)model, (void)x, (void)function, 1; }
int model_get_derivatives(FmuModel *model, double *dx, const char *function)
{ return (void)model, (void)dx, (void)function, 1; }

/* The signed penetration of the deepest bushing point at the current inputs (a contact onset is its zero crossing),
 * touching (0) as DBL_MIN: no exact zero that CVODE's root check cannot leave; 0 (logged) on failure. */
int model_get_event_indicators(FmuModel *model, double *z, const char *function)
{
    if (!joint_evaluate(model, function, "the event indicator"))
        return 0;
    z[0] = model->result[R_PENETRATION] != 0.0 ? model->result[R_PENETRATION] : DBL_MIN;
    return 1;
}

/* A contact begins or ends: the contact-onset bookkeeping at the current inputs; nothing if an accepted step at
 * these inputs did it (from the contact before that step's wear, as in process). */
int model_event_update(FmuModel *model, const char *function)
{
    if (model->onsets_accepted)
        return 1;
    if (!joint_evaluate(model, function, "the event indicator"))
        return 0;
    int32_t changed = 0;
    if (!kernel_ok(model, "wearjoint_update_contact_memory failed",
                   wearjoint_update_contact_memory(&changed, NULL, model->result, model->joint_parameters,
                                                   model->memory)))
        return 0;
    if (changed)
        model->forces_stale = 1;
    return 1;
}

/* Wear and the onset bookkeeping over the step since the last completed one, at the current inputs: a status.  A time
 * before that step's end by rounding (TIME_ROUNDING; CVODE's event location in fmusim: 1.4e-16 s) is a step of none. */
int model_completed_integrator_step(FmuModel *model, const char *function)
{
    double dt = model->time - model->last_accepted_time;
    if (dt < 0.0 && -dt <= TIME_ROUNDING * fmax(fabs(model->last_accepted_time), 1e-3))
        dt = 0.0;
    else if (dt < 0.0) {
        fmu_log(&model->host, FMU_ERROR, "%s: step rejected: the time t=%.17g s is before the last completed step's "
                "end, %.17g s", function, model->time, model->last_accepted_time);
        return FMU_ERROR;
    }
    int status = accept_step(model, dt, 0, function);
    if (status <= FMU_WARNING)
        model->last_accepted_time = model->time;
    return status;
}
