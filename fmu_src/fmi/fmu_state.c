/* FMU-state objects of both FMI layers (see fmu_model.h, "FMU states").
 *
 * In memory a state is the model's values copied as they are (model_get_state / model_set_state):
 * a host gives back what it got, so getFMUstate and setFMUstate copy arrays and check only the
 * size.  Serialised it is the state format (wearjoint/core/state_format.py: versioned header,
 * CRC-32C): written from the in-memory values, and bytes that come from outside pass every check
 * of the format before they become a state. */
#include "fmu_model.h"

#include <string.h>

typedef struct {
    size_t size;        /* bytes of values */
    double values[];    /* the model's in-memory state */
} FmuState;

static FmuState *new_state(FmuModel *model, size_t size)
{
    FmuHost *host = model_host(model);
    FmuState *s = host->allocate(host->environment, 1, sizeof *s + size);
    if (s == NULL)
        fmu_log(host, FMU_ERROR, "FMU state: out of memory");
    else
        s->size = size;
    return s;
}

static void release_state(FmuModel *model, FmuState *s)
{
    FmuHost *host = model_host(model);
    if (s != NULL)
        host->release(host->environment, s);
}

int fmu_get_state(FmuModel *model, void **state, int initialised, const char *function)
{
    if (state == NULL) {
        fmu_log(model_host(model), FMU_ERROR, "%s: NULL state pointer", function);
        return FMU_ERROR;
    }
    size_t size = model_state_size(model);
    FmuState *s = *state;
    if (s == NULL) {
        if ((s = new_state(model, size)) == NULL)
            return FMU_ERROR;
        *state = s;
    } else if (s->size != size) {
        fmu_log(model_host(model), FMU_ERROR, "%s: the state given to overwrite is not of this FMU", function);
        return FMU_ERROR;
    }
    model_get_state(model, s->values, initialised);
    return FMU_OK;
}

int fmu_set_state(FmuModel *model, const void *state, int *initialised, const char *function)
{
    const FmuState *s = state;
    if (s == NULL) {
        fmu_log(model_host(model), FMU_ERROR, "%s: NULL state", function);
        return FMU_ERROR;
    }
    if (s->size != model_state_size(model)) {
        fmu_log(model_host(model), FMU_ERROR, "%s: a state of %zu bytes, this instance's have %zu", function, s->size,
                model_state_size(model));
        return FMU_ERROR;
    }
    return model_set_state(model, s->values, initialised, function) ? FMU_OK : FMU_ERROR;
}

int fmu_free_state(FmuModel *model, void **state, const char *function)
{
    if (state == NULL) {
        fmu_log(model_host(model), FMU_ERROR, "%s: NULL state pointer", function);
        return FMU_ERROR;
    }
    release_state(model, *state);
    *state = NULL;
    return FMU_OK;
}

int fmu_serialized_state_size(FmuModel *model, const void *state, size_t *size, const char *function)
{
    const FmuState *s = state;
    if (s == NULL || size == NULL) {
        fmu_log(model_host(model), FMU_ERROR, "%s: NULL state or size pointer", function);
        return FMU_ERROR;
    }
    *size = model_serialized_state_size(model, s->values);
    return FMU_OK;
}

int fmu_serialize_state(FmuModel *model, const void *state, unsigned char *bytes, size_t size, const char *function)
{
    const FmuState *s = state;
    size_t needed = s != NULL ? model_serialized_state_size(model, s->values) : 0;
    if (s == NULL || bytes == NULL || size < needed) {
        fmu_log(model_host(model), FMU_ERROR, "%s: NULL state or buffer, or a buffer of %zu bytes for a state of %zu",
                function, size, needed);
        return FMU_ERROR;
    }
    model_serialize_state(model, s->values, bytes);
    return FMU_OK;
}

/* Checked into a new state, so that a state given to overwrite changes only if the bytes are valid. */
int fmu_deserialize_state(FmuModel *model, const unsigned char *bytes, size_t size, void **state,
                          const char *function)
{
    if (bytes == NULL || state == NULL) {
        fmu_log(model_host(model), FMU_ERROR, "%s: NULL bytes or state pointer", function);
        return FMU_ERROR;
    }
    size_t memory_size = model_state_size(model);
    FmuState *old = *state;
    if (old != NULL && old->size != memory_size) {
        fmu_log(model_host(model), FMU_ERROR, "%s: the state given to overwrite is not of this FMU", function);
        return FMU_ERROR;
    }
    FmuState *s = new_state(model, memory_size);
    if (s == NULL)
        return FMU_ERROR;
    int ok = model_deserialize_state(model, bytes, size, s->values, function);
    if (ok && old == NULL) {
        *state = s;
        return FMU_OK;
    }
    if (ok)
        memcpy(old->values, s->values, memory_size);
    release_state(model, s);
    return ok ? FMU_OK : FMU_ERROR;
}
