/* The FMI 2.0 layer's instance, shared by the files of the layer (fmi2Functions.c, fmi2_values.c,
 * fmi2_cosimulation.c, fmi2_model_exchange.c): its modes (the FMI 2.0 call sequence), the model it
 * drives (fmu_model.h), the log macro and the checks every call makes.  Internal to the layer: the
 * checks are static inline, so the binary exports the fmi2* functions only.
 */
#ifndef WEARJOINT_FMI2_INSTANCE_H
#define WEARJOINT_FMI2_INSTANCE_H

#include <stddef.h>

#include "fmi2Functions.h"
#include "fmu_model.h"

typedef enum {
    MODE_INSTANTIATED, MODE_INITIALIZATION, MODE_STEP_COMPLETE, MODE_EVENT, MODE_CONTINUOUS, MODE_TERMINATED
} Mode;
static const char *const MODE_NAMES[] = {"instantiated", "initialization mode", "step complete", "event mode",
                                         "continuous-time mode", "terminated"};
#define M(mode) (1u << (mode))
#define INITIALISED (M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | M(MODE_CONTINUOUS) | M(MODE_TERMINATED))
#define READABLE (M(MODE_INITIALIZATION) | INITIALISED)
#define SETTABLE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP_COMPLETE) | M(MODE_EVENT) | \
                  M(MODE_CONTINUOUS))

typedef struct {
    FmuModel *model;
    fmi2CallbackFunctions callbacks;
    fmi2Type type;
    Mode mode;
    fmi2Boolean discarded;   /* the last fmi2DoStep returned fmi2Discard: the joint cannot go on (fmi2Terminated) */
    double stop_time;        /* the master's stop time [s] (INFINITY: none): no step passes it */
} Instance;

#define LOG(inst, ...) fmu_log(model_host((inst)->model), __VA_ARGS__)

#define FMI_VERSION 2
#define FMI_STATUS fmi2Status
#define MODE_STEPPING MODE_STEP_COMPLETE
#define IS_CO_SIMULATION(inst) ((inst)->type == fmi2CoSimulation)
#define FMI_CALL_SEQUENCE "FMI 2.0 call sequence"
#include "fmi_checks.h"

#endif
