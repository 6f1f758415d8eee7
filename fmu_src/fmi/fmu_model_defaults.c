/* The optional parts of the model interface (fmu_model.h) as "not provided" (-1: the FMI layer answers
 * fmiError naming the call), for a model whose generated model_variables.h does not declare the capability
 * -- as the Reference-FMUs' cosimulation.c does with HAS_* macros:
 *   MODEL_HAS_INTEGERS                  Integer / enumeration variables (model_get/set_integer)
 *   MODEL_HAS_STRUCTURAL_PARAMETERS     structural parameters and Configuration Mode
 *   MODEL_HAS_DIRECTIONAL_DERIVATIVES   directional derivatives (providesDirectionalDerivative)
 * A new native model implements the required functions of fmu_model.h and these only where it has them. */
#include "model_variables.h"

#ifndef MODEL_HAS_INTEGERS
int model_get_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t *value, const char *function)
{
    (void)model, (void)fmi_version, (void)vr, (void)value, (void)function;
    return -1;
}

int model_set_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t value, int parameters_settable,
                      const char *function)
{
    (void)model, (void)fmi_version, (void)vr, (void)value, (void)parameters_settable, (void)function;
    return -1;
}
#endif

#ifndef MODEL_HAS_STRUCTURAL_PARAMETERS
int model_get_structural(FmuModel *model, unsigned vr, int configuration, uint64_t *value)
{
    (void)model, (void)vr, (void)configuration, (void)value;
    return -1;
}

int model_set_structural(FmuModel *model, unsigned vr, uint64_t value, int configuration, int settable,
                         const char *state, const char *function)
{
    (void)model, (void)vr, (void)value, (void)configuration, (void)settable, (void)state, (void)function;
    return -1;
}

void model_enter_configuration(FmuModel *model) { (void)model; }

int model_exit_configuration(FmuModel *model)
{
    (void)model;
    return 1;
}
#endif

#ifndef MODEL_HAS_DIRECTIONAL_DERIVATIVES
int model_directional_derivative(FmuModel *model, int fmi_version, const unsigned *unknowns, size_t n_unknowns,
                                 const unsigned *knowns, size_t n_knowns, const double *seed, double *sensitivity,
                                 const char *function)
{
    (void)model, (void)fmi_version, (void)unknowns, (void)n_unknowns, (void)knowns, (void)n_knowns, (void)seed,
        (void)sensitivity, (void)function;
    return -1;
}
#endif
