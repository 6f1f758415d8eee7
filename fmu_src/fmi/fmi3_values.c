/* FMI 3.0 layer (fmi3Functions.c): the variables' values -- fmi3Get/SetFloat64 (an array counts its
 * size in nValues), Int64 (the enumerations), UInt64 (the structural parameters), the types this FMU
 * has no variables of -- and fmi3GetDirectionalDerivative.  A parameter may be set until
 * fmi3ExitInitializationMode only, a structural parameter in Configuration Mode.
 */
#include <stdint.h>

#include "fmi3_instance.h"

/* The number of values nvr Float64 value references stand for (an array counts its size);
 * 0 (logged) if one is not a Float64 variable or the count is not n_values (the argument ``count``). */
static int float64_values(const Instance *inst, const char *function, const fmi3ValueReference vr[], size_t nvr,
                          size_t n_values, const char *count)
{
    size_t needed = 0;
    for (size_t i = 0; i < nvr; i++) {
        size_t n = model_float64_count(inst->model, 3, vr[i]);
        if (n == 0) {
            access_refused(inst, function, vr[i], "a Float64", 0, -1);
            return 0;
        }
        needed += n;
    }
    if (needed != n_values) {
        char sizes[128];
        LOG(inst, fmi3Error, "%s: %s=%zu, but the %zu value references stand for %zu values%s", function, count,
            n_values, nvr, needed, model_array_sizes(inst->model, sizes, sizeof sizes));
        return 0;
    }
    return 1;
}

/* Scalars of one value each: nValues must equal nValueReferences. */
static int scalar_values(const Instance *inst, const char *function, size_t nvr, size_t n_values)
{
    if (nvr == n_values)
        return 1;
    LOG(inst, fmi3Error, "%s: nValues=%zu for %zu scalar variables", function, n_values, nvr);
    return 0;
}

/* ------------------------------------------------------------------ values */
fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 value[],
                          size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetFloat64", nvr, vr, value) || !mode_is(inst, "fmi3GetFloat64", READABLE) ||
        !float64_values(inst, "fmi3GetFloat64", vr, nvr, n_values, "nValues"))
        return fmi3Error;
    size_t k = 0;
    for (size_t i = 0; i < nvr; i++) {
        if (model_get_float64(inst->model, 3, vr[i], value + k, "fmi3GetFloat64") != 1)
            return fmi3Error;
        k += model_float64_count(inst->model, 3, vr[i]);
    }
    return fmi3OK;
}

/* fmi3SetFloat64, fmi3SetInt64 (scalars): each value through the model's ``model_set`` (model_set_float64,
 * model_set_integer), up to the first it refuses. */
#define SETTER(function, type, model_set, a_type)                                                                  \
    fmi3Status function(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const type value[],     \
                        size_t n_values)                                                                          \
    {                                                                                                              \
        Instance *inst = instance;                                                                                 \
        if (!arrays_given(inst, #function, nvr, vr, value) || !mode_is(inst, #function, SETTABLE) ||               \
            !scalar_values(inst, #function, nvr, n_values))                                                        \
            return fmi3Error;                                                                                      \
        for (size_t i = 0; i < nvr; i++) {                                                                         \
            int done = model_set(inst->model, 3, vr[i], value[i], parameters_settable(inst), #function);           \
            if (done != 1)                                                                                         \
                return (fmi3Status)access_refused(inst, #function, vr[i], a_type, 1, done);                        \
        }                                                                                                          \
        return fmi3OK;                                                                                             \
    }

SETTER(fmi3SetFloat64, fmi3Float64, model_set_float64, "a Float64")
SETTER(fmi3SetInt64, fmi3Int64, model_set_integer, "an Enumeration")

/* The enumerations: their item values. */
fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 value[],
                        size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetInt64", nvr, vr, value) || !mode_is(inst, "fmi3GetInt64", READABLE) ||
        !scalar_values(inst, "fmi3GetInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        int64_t v = 0;
        int done = model_get_integer(inst->model, 3, vr[i], &v, "fmi3GetInt64");
        if (done != 1)
            return (fmi3Status)access_refused(inst, "fmi3GetInt64", vr[i], "an Enumeration", 0, done);
        value[i] = v;
    }
    return fmi3OK;
}

/* The structural parameters: readable in every state, set in Configuration Mode. */
fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 value[],
                         size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3GetUInt64", nvr, vr, value) || !scalar_values(inst, "fmi3GetUInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        if (model_get_structural(inst->model, vr[i], inst->mode == MODE_CONFIGURATION, &value[i]) != 1)
            return (fmi3Status)access_refused(inst, "fmi3GetUInt64", vr[i], "a UInt64", 0, -1);
    }
    return fmi3OK;
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 value[],
                         size_t n_values)
{
    Instance *inst = instance;
    if (!arrays_given(inst, "fmi3SetUInt64", nvr, vr, value) || !scalar_values(inst, "fmi3SetUInt64", nvr, n_values))
        return fmi3Error;
    for (size_t i = 0; i < nvr; i++) {
        int done = model_set_structural(inst->model, vr[i], value[i], inst->mode == MODE_CONFIGURATION,
                                        (M(inst->mode) & SETTABLE) != 0, MODE_NAMES[inst->mode], "fmi3SetUInt64");
        if (done != 1)
            return (fmi3Status)access_refused(inst, "fmi3SetUInt64", vr[i], "a UInt64", 1, done);
    }
    return fmi3OK;
}

/* The types this FMU has no variables of. */
#define NO_VARIABLES_OF_TYPE(function, type, qualifier)                                                          \
    fmi3Status function(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, qualifier type value[], \
                        size_t n_values)                                                                         \
    {                                                                                                            \
        (void)n_values;                                                                                          \
        return (fmi3Status)no_variables_of_type(instance, #function, #type, nvr, vr, value);                     \
    }

NO_VARIABLES_OF_TYPE(fmi3GetFloat32, fmi3Float32, )
NO_VARIABLES_OF_TYPE(fmi3SetFloat32, fmi3Float32, const)
NO_VARIABLES_OF_TYPE(fmi3GetInt8, fmi3Int8, )
NO_VARIABLES_OF_TYPE(fmi3SetInt8, fmi3Int8, const)
NO_VARIABLES_OF_TYPE(fmi3GetUInt8, fmi3UInt8, )
NO_VARIABLES_OF_TYPE(fmi3SetUInt8, fmi3UInt8, const)
NO_VARIABLES_OF_TYPE(fmi3GetInt16, fmi3Int16, )
NO_VARIABLES_OF_TYPE(fmi3SetInt16, fmi3Int16, const)
NO_VARIABLES_OF_TYPE(fmi3GetUInt16, fmi3UInt16, )
NO_VARIABLES_OF_TYPE(fmi3SetUInt16, fmi3UInt16, const)
NO_VARIABLES_OF_TYPE(fmi3GetInt32, fmi3Int32, )
NO_VARIABLES_OF_TYPE(fmi3SetInt32, fmi3Int32, const)
NO_VARIABLES_OF_TYPE(fmi3GetUInt32, fmi3UInt32, )
NO_VARIABLES_OF_TYPE(fmi3SetUInt32, fmi3UInt32, const)
NO_VARIABLES_OF_TYPE(fmi3GetBoolean, fmi3Boolean, )
NO_VARIABLES_OF_TYPE(fmi3SetBoolean, fmi3Boolean, const)
NO_VARIABLES_OF_TYPE(fmi3GetString, fmi3String, )
NO_VARIABLES_OF_TYPE(fmi3SetString, fmi3String, const)

/* sensitivity = J seed, J the partial derivatives of the unknowns (outputs; an array counts its size) with respect
 * to the knowns (inputs). */
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,
                                        const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[],
                                        size_t n_seed, fmi3Float64 sensitivity[], size_t n_sensitivity)
{
    Instance *inst = instance;
    const char *function = "fmi3GetDirectionalDerivative";
    if (!arrays_given(inst, function, n_unknowns, unknowns, sensitivity) ||
        !arrays_given(inst, function, n_knowns, knowns, seed) || !mode_is(inst, function, READABLE) ||
        !float64_values(inst, function, unknowns, n_unknowns, n_sensitivity, "nSensitivity") ||
        !float64_values(inst, function, knowns, n_knowns, n_seed, "nSeed"))
        return fmi3Error;
    int done = model_directional_derivative(inst->model, 3, unknowns, n_unknowns, knowns, n_knowns, seed, sensitivity,
                                            function);
    if (done == -1) {
        LOG(inst, fmi3Error, "%s: providesDirectionalDerivatives is false for this FMU", function);
        return fmi3Error;
    }
    return done == 1 ? fmi3OK : fmi3Error;
}
