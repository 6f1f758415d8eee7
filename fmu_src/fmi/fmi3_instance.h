/* The FMI 3.0 layer's instance, shared by the files of the layer (fmi3Functions.c, fmi3_values.c,
 * fmi3_not_provided.c, fmi3_cosimulation.c, fmi3_model_exchange.c): its modes (the FMI 3.0 states),
 * the model it drives (fmu_model.h), the log macro and the checks every call makes.  Internal to the
 * layer: the checks are static inline, so the binary exports the fmi3* functions only.
 */
#ifndef WEARJOINT_FMI3_INSTANCE_H
#define WEARJOINT_FMI3_INSTANCE_H

#include <stddef.h>

#include "fmi3Functions.h"
#include "fmu_model.h"

typedef enum {
    MODE_INSTANTIATED, MODE_CONFIGURATION, MODE_INITIALIZATION, MODE_STEP, MODE_EVENT, MODE_CONTINUOUS,
    MODE_TERMINATED
} Mode;
static const char *const MODE_NAMES[] = {"Instantiated", "Configuration Mode", "Initialization Mode", "Step Mode",
                                         "Event Mode", "Continuous-Time Mode", "Terminated"};
#define M(mode) (1u << (mode))
#define INITIALISED (M(MODE_STEP) | M(MODE_EVENT) | M(MODE_CONTINUOUS) | M(MODE_TERMINATED))
#define READABLE (M(MODE_INITIALIZATION) | INITIALISED)
#define SETTABLE (M(MODE_INSTANTIATED) | M(MODE_INITIALIZATION) | M(MODE_STEP) | M(MODE_EVENT) | M(MODE_CONTINUOUS))

typedef struct {
    FmuModel *model;
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;
    int co_simulation;             /* 1: Co-Simulation, 0: Model Exchange */
    Mode mode;
    double stop_time;        /* the master's stop time [s] (INFINITY: none): no step passes it */
} Instance;

#define LOG(inst, ...) fmu_log(model_host((inst)->model), __VA_ARGS__)

#define FMI_VERSION 3
#define FMI_STATUS fmi3Status
#define MODE_STEPPING MODE_STEP
#define IS_CO_SIMULATION(inst) ((inst)->co_simulation)
#define FMI_CALL_SEQUENCE "FMI 3.0 call sequence"
#include "fmi_checks.h"

#endif
