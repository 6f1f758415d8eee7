/* FMI 2.0 layer (fmi2Functions.c): the variables' values -- fmi2Get/Set of Reals and Integers (the
 * model's), of Booleans and Strings (this FMU has none) -- and fmi2GetDirectionalDerivative.  A
 * parameter may be set until fmi2ExitInitializationMode only.
 */
#include <stdint.h>

#include "fmi2_instance.h"

static void not_a_variable(const Instance *inst, const char *function, fmi2ValueReference vr, const char *what)
{
    char name[96];
    model_variable_name(inst->model, 2, vr, name, sizeof name);
    LOG(inst, fmi2Error, "%s: %s%s", function, name, what);
}

/* ------------------------------------------------------------------ values */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetReal", nvr, vr, value) ||
        !mode_is(inst, "fmi2GetReal", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {   /* FMI 2.0 has no arrays: every Real the model gets is one value */
        int done = model_get_float64(inst->model, 2, vr[i], &value[i], "fmi2GetReal");
        if (done == -1)
            not_a_variable(inst, "fmi2GetReal", vr[i], " is not a Real variable");
        if (done != 1)
            return fmi2Error;
    }
    return fmi2OK;
}

/* A parameter may be set before exitInitializationMode only. */
static int parameters_settable(const Instance *inst)
{
    return inst->mode == MODE_INSTANTIATED || inst->mode == MODE_INITIALIZATION;
}

/* After a set: -1 the variable cannot be set, -2 a parameter after initialisation (logged here). */
static fmi2Status set_failed(const Instance *inst, const char *function, fmi2ValueReference vr, int done)
{
    char name[96];
    model_variable_name(inst->model, 2, vr, name, sizeof name);
    if (done == -1)
        LOG(inst, fmi2Error, "%s: variable %s cannot be set", function, name);
    else if (done == -2)
        LOG(inst, fmi2Error, "%s: parameter %s is fixed: set it before fmi2ExitInitializationMode", function, name);
    return fmi2Error;
}

#define SETTABLE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | \
                  M(MODE_CONTINUOUS))

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetReal", nvr, vr, value) || !mode_is(inst, "fmi2SetReal", SETTABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_float64(inst->model, 2, vr[i], value[i], parameters_settable(inst), "fmi2SetReal");
        if (done != 1)
            return set_failed(inst, "fmi2SetReal", vr[i], done);
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetInteger", nvr, vr, value) ||
        !mode_is(inst, "fmi2GetInteger", M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int64_t v = 0;
        int done = model_get_integer(inst->model, 2, vr[i], &v, "fmi2GetInteger");
        if (done == -1)
            not_a_variable(inst, "fmi2GetInteger", vr[i], " is not an Integer variable");
        if (done != 1)
            return fmi2Error;
        value[i] = (fmi2Integer)v;
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2SetInteger", nvr, vr, value) || !mode_is(inst, "fmi2SetInteger", SETTABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_integer(inst->model, 2, vr[i], value[i], parameters_settable(inst), "fmi2SetInteger");
        if (done != 1)
            return set_failed(inst, "fmi2SetInteger", vr[i], done);
    }
    return fmi2OK;
}

#define NO_VARIABLES_OF_TYPE(function, type, qualifier)                                                       \
    fmi2Status function(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, qualifier type value[])    \
    {                                                                                                         \
        Instance *inst = c;                                                                                   \
        if (!arrays_given(inst, #function, nvr, vr, value))                                                   \
            return fmi2Error;                                                                                 \
        if (nvr == 0)                                                                                         \
            return fmi2OK;                                                                                    \
        LOG(inst, fmi2Error, "%s: this FMU has no %s variables (valueReference %u)", #function,  \
                  #type, (unsigned)vr[0]);                                                                    \
        return fmi2Error;                                                                                     \
    }

NO_VARIABLES_OF_TYPE(fmi2GetBoolean, fmi2Boolean, )
NO_VARIABLES_OF_TYPE(fmi2SetBoolean, fmi2Boolean, const)
NO_VARIABLES_OF_TYPE(fmi2GetString, fmi2String, )
NO_VARIABLES_OF_TYPE(fmi2SetString, fmi2String, const)

/* dv_unknown = J dv_known, J the partial derivatives of the unknowns (outputs) with respect to the knowns (inputs). */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[], size_t n_unknown,
                                        const fmi2ValueReference known[], size_t n_known, const fmi2Real dv_known[],
                                        fmi2Real dv_unknown[])
{
    Instance *inst = c;
    const char *function = "fmi2GetDirectionalDerivative";
    if (!arrays_given(inst, function, n_unknown, unknown, dv_unknown) ||
        !arrays_given(inst, function, n_known, known, dv_known) ||
        !mode_is(inst, function, M(MODE_INITIALIZATION) | INITIALISED))
        return fmi2Error;
    int done = model_directional_derivative(inst->model, 2, unknown, n_unknown, known, n_known, dv_known, dv_unknown,
                                            function);
    if (done == -1)
        LOG(inst, fmi2Error, "%s: providesDirectionalDerivative is false for this FMU", function);
    return done == 1 ? fmi2OK : fmi2Error;
}
