/* FMI 3.0 layer (fmi3Functions.c): the functions this FMU does not provide -- Binary variables,
 * clocks, discrete-state evaluation, per-element dependencies, adjoint and output derivatives.  Each
 * logs why and returns fmi3Error.
 */
#include "fmi3_instance.h"

/* (the unused parameters of these functions are named, for the reader; -Wno-unused-parameter) */
#define NO_BINARY "this FMU has no Binary variables"
#define NO_CLOCKS "this FMU has no clocks"
NOT_PROVIDED(fmi3GetBinary, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, size_t value_sizes[],
              fmi3Binary values[], size_t n_values),
             NO_BINARY)
NOT_PROVIDED(fmi3SetBinary, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const size_t value_sizes[],
              const fmi3Binary values[], size_t n_values),
             NO_BINARY)
NOT_PROVIDED(fmi3GetClock, instance, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock values[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetClock, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock values[]), NO_CLOCKS)
NOT_PROVIDED(fmi3GetIntervalDecimal, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 intervals[],
              fmi3IntervalQualifier qualifiers[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3GetIntervalFraction, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 counters[],
              fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3GetShiftDecimal, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 shifts[]), NO_CLOCKS)
NOT_PROVIDED(fmi3GetShiftFraction, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 counters[],
              fmi3UInt64 resolutions[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetIntervalDecimal, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 intervals[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetIntervalFraction, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 counters[],
              const fmi3UInt64 resolutions[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetShiftDecimal, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 shifts[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3SetShiftFraction, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 counters[],
              const fmi3UInt64 resolutions[]),
             NO_CLOCKS)
NOT_PROVIDED(fmi3ActivateModelPartition, instance,
             (fmi3Instance instance, fmi3ValueReference clock_reference, fmi3Float64 activation_time), NO_CLOCKS)
NOT_PROVIDED(fmi3EvaluateDiscreteStates, instance, (fmi3Instance instance),
             "providesEvaluateDiscreteStates is false for this FMU")
NOT_PROVIDED(fmi3GetNumberOfVariableDependencies, instance,
             (fmi3Instance instance, fmi3ValueReference vr, size_t *n_dependencies),
             "providesPerElementDependencies is false for this FMU (see the ModelStructure)")
NOT_PROVIDED(fmi3GetVariableDependencies, instance,
             (fmi3Instance instance, fmi3ValueReference dependent, size_t element_indices_of_dependent[],
              fmi3ValueReference independents[], size_t element_indices_of_independents[],
              fmi3DependencyKind dependency_kinds[], size_t n_dependencies),
             "providesPerElementDependencies is false for this FMU (see the ModelStructure)")
NOT_PROVIDED(fmi3GetAdjointDerivative, instance,
             (fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,
              const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[], size_t n_seed,
              fmi3Float64 sensitivity[], size_t n_sensitivity),
             "providesAdjointDerivatives is false for this FMU")
NOT_PROVIDED(fmi3GetOutputDerivatives, instance,
             (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 orders[],
              fmi3Float64 values[], size_t n_values),
             "maxOutputDerivativeOrder is 0 for this FMU")
