/* The FMU-state functions of the FMI 2.0 and 3.0 layers, defined once: FMU_STATE_FUNCTIONS expands, in
 * fmi2Functions.c and fmi3Functions.c, to the six functions with the version's names and types, each a
 * call of fmu_state.c (the model's in-memory and serialised states) on a checked instance.  Included after
 * the version's instance header (fmi_checks.h: mode_is, mode_after_set_state).  ``settable``: the modes in
 * which a state may be set. */
#ifndef WEARJOINT_FMI_STATE_FUNCTIONS_H
#define WEARJOINT_FMI_STATE_FUNCTIONS_H

#define FMU_STATE_FUNCTIONS(Status, Component, State, Byte, get, set, free_state, size, serialize, deserialize,     \
                            settable)                                                                            \
    Status get(Component instance, State *state)                                                                 \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        if (inst == NULL)                                                                                        \
            return (Status)FMU_ERROR;                                                                            \
        return (Status)fmu_get_state(inst->model, state, (M(inst->mode) & INITIALISED) != 0, #get);             \
    }                                                                                                            \
                                                                                                                 \
    /* the instance's mode follows the state's initialised flag */                                               \
    Status set(Component instance, State state)                                                                  \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        if (inst == NULL || !mode_is(inst, #set, settable))                                                      \
            return (Status)FMU_ERROR;                                                                            \
        int initialised = -1;                                                                                    \
        Status status = (Status)fmu_set_state(inst->model, state, &initialised, #set);                           \
        mode_after_set_state(inst, initialised);                                                                 \
        return status;                                                                                           \
    }                                                                                                            \
                                                                                                                 \
    Status free_state(Component instance, State *state)                                                          \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        return inst == NULL ? (Status)FMU_ERROR : (Status)fmu_free_state(inst->model, state, #free_state);        \
    }                                                                                                            \
                                                                                                                 \
    Status size(Component instance, State state, size_t *n_bytes)                                                \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        return inst == NULL ? (Status)FMU_ERROR : (Status)fmu_serialized_state_size(inst->model, state, n_bytes, \
                                                                                    #size);                      \
    }                                                                                                            \
                                                                                                                 \
    Status serialize(Component instance, State state, Byte bytes[], size_t n_bytes)                             \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        return inst == NULL ? (Status)FMU_ERROR                                                                  \
                            : (Status)fmu_serialize_state(inst->model, state, (unsigned char *)bytes, n_bytes,   \
                                                          #serialize);                                           \
    }                                                                                                            \
                                                                                                                 \
    Status deserialize(Component instance, const Byte bytes[], size_t n_bytes, State *state)                     \
    {                                                                                                            \
        Instance *inst = instance;                                                                               \
        return inst == NULL ? (Status)FMU_ERROR                                                                  \
                            : (Status)fmu_deserialize_state(inst->model, (const unsigned char *)bytes, n_bytes,  \
                                                            state, #deserialize);                                \
    }

#endif
