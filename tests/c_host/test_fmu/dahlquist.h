/* dahlquist.h -- the test FMU's types and macros, shared by dahlquist.c (instance, values,
 * stepping) and dahlquist_states.c (FMU states, status queries); see dahlquist.c. */
#ifndef DAHLQUIST_H
#define DAHLQUIST_H

#include <stdint.h>

#include "fmi2Functions.h"

#define GUID "{a3f0e8de-5c1b-4d7e-9a61-0d5a41c15701}"
#define MAGIC "DAHLQST1"
#define SERIALIZED_SIZE (8 + 5 * 8 + 4 + 4)

enum { VR_X = 0, VR_K = 1, VR_X0 = 2, VR_U = 3, VR_NSTEPS = 4, VR_RESOURCE = 5 };
typedef enum { INSTANTIATED = 1, INIT_MODE = 2, STEP_MODE = 4, TERMINATED = 8 } Phase;

typedef struct {
    double time, x, k, x0, u;
    int32_t n_steps;
    int32_t phase;
} Data;

typedef struct {
    char magic[8];
    Data d;
} State;

typedef struct {
    Data d;
    const fmi2CallbackFunctions *cb;
    char *name;
    char *resource;
    int logging;
} Instance;

#define LOG(inst, status, category, ...)                                                  \
    do {                                                                                  \
        if ((inst)->cb->logger != NULL && ((inst)->logging || (status) > fmi2Warning))   \
            (inst)->cb->logger((inst)->cb->componentEnvironment, (inst)->name, (status), \
                               (category), __VA_ARGS__);                                  \
    } while (0)

#define ERROR(inst, ...)                                                                  \
    do {                                                                                  \
        LOG(inst, fmi2Error, "logStatusError", __VA_ARGS__);                              \
        return fmi2Error;                                                                 \
    } while (0)

#define ALLOWED(inst, fn, phases)                                                         \
    do {                                                                                  \
        if (!((inst)->d.phase & (phases)))                                                \
            ERROR(inst, "%s: not allowed in phase %d", fn, (int)(inst)->d.phase);         \
    } while (0)

#endif
