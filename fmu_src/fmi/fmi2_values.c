/* FMI 2.0 layer (fmi2Functions.c): the variables' values -- fmi2Get/Set of Reals and Integers (the
 * model's), of Booleans and Strings (this FMU has none) -- and fmi2GetDirectionalDerivative.  A
 * parameter may be set until fmi2ExitInitializationMode only.
 */
#include <stdint.h>

#include "fmi2_instance.h"

/* ------------------------------------------------------------------ values */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetReal", nvr, vr, value) || !mode_is(inst, "fmi2GetReal", READABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {   /* FMI 2.0 has no arrays: every Real the model gets is one value */
        int done = model_get_float64(inst->model, 2, vr[i], &value[i], "fmi2GetReal");
        if (done != 1)
            return (fmi2Status)access_refused(inst, "fmi2GetReal", vr[i], "a Real", 0, done);
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    Instance *inst = c;
    if (!arrays_given(inst, "fmi2GetInteger", nvr, vr, value) || !mode_is(inst, "fmi2GetInteger", READABLE))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++) {
        int64_t v = 0;
        int done = model_get_integer(inst->model, 2, vr[i], &v, "fmi2GetInteger");
        if (done != 1)
            return (fmi2Status)access_refused(inst, "fmi2GetInteger", vr[i], "an Integer", 0, done);
        value[i] = (fmi2Integer)v;
    }
    return fmi2OK;
}

/* fmi2SetReal, fmi2SetInteger: each value through the model's ``model_set`` (model_set_float64,
 * model_set_integer), up to the first it refuses. */
#define SETTER(function, type, model_set, a_type)                                                             \
    fmi2Status function(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const type value[])      \
    {                                                                                                         \
        Instance *inst = c;                                                                                   \
        if (!arrays_given(inst, #function, nvr, vr, value) || !mode_is(inst, #function, SETTABLE))            \
            return fmi2Error;                                                                                 \
        for (size_t i = 0; i < nvr; i++) {                                                                    \
            int done = model_set(inst->model, 2, vr[i], value[i], parameters_settable(inst), #function);      \
            if (done != 1)                                                                                    \
                return (fmi2Status)access_refused(inst, #function, vr[i], a_type, 1, done);                   \
        }                                                                                                     \
        return fmi2OK;                                                                                        \
    }

SETTER(fmi2SetReal, fmi2Real, model_set_float64, "a Real")
SETTER(fmi2SetInteger, fmi2Integer, model_set_integer, "an Integer")

#define NO_VARIABLES_OF_TYPE(function, type, qualifier)                                                    \
    fmi2Status function(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, qualifier type value[]) \
    {                                                                                                      \
        return (fmi2Status)no_variables_of_type(c, #function, #type, nvr, vr, value);                      \
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
        !arrays_given(inst, function, n_known, known, dv_known) || !mode_is(inst, function, READABLE))
        return fmi2Error;
    int done = model_directional_derivative(inst->model, 2, unknown, n_unknown, known, n_known, dv_known, dv_unknown,
                                            function);
    if (done == -1)
        LOG(inst, fmi2Error, "%s: providesDirectionalDerivative is false for this FMU", function);
    return done == 1 ? fmi2OK : fmi2Error;
}
