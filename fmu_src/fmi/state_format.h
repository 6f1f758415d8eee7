/* The state format's kernels (wearjoint/core/state_format.py, entry points of
 * wearjoint/fmu/state_entry_points.py), compiled ahead of time into every native FMU with numba's
 * calling convention (int32 status; a pointer for the return value; one for exception information,
 * never written).  Every model's serialised FMU state is one of these: little-endian, versioned header,
 * CRC-32C (in memory a state is the model's values as they are: fmu_model.h). */
#ifndef WEARJOINT_STATE_FORMAT_H
#define WEARJOINT_STATE_FORMAT_H

#include <stdint.h>

/* The same kernels write, check and read ClearanceJoint's states in process.  The size of a state
 * with n_head head values and n_points wear depths. */
int32_t wearjoint_state_size(int64_t *size, void *excinfo, int64_t n_head, int64_t n_points);

/* Write a state (contents kind, head values, contact memory, wear depths) into data[size], checksum last. */
int32_t wearjoint_write_state(int32_t *status, void *excinfo, uint8_t *data, int64_t size, int64_t contents,
                              const double *head, int64_t n_head, const double *memory, const double *wear_depth,
                              int64_t n_points);

/* *problem = 0 if data[size] is an intact state of this contents kind, head size and n_points (magic,
 * version, size, checksum, contents, n_points), else the first problem; values[4]: what it compared. */
int32_t wearjoint_check_header(int32_t *problem, void *excinfo, const uint8_t *data, int64_t size, int64_t contents,
                               int64_t n_head, int64_t n_points, double *values);

/* Copy a checked state's head values, contact memory and wear depths out. */
int32_t wearjoint_read_state(int32_t *status, void *excinfo, const uint8_t *data, int64_t size, double *head,
                             int64_t n_head, double *memory, double *wear_depth, int64_t n_points);

/* *problem = 0 if the values are in range (the head's time and initialised flag, the contact memory with an
 * onset velocity >= velocity_floor, the wear depths in [0, bushing_radius]), else the first problem;
 * values[4]: what it compared. */
int32_t wearjoint_check_values(int32_t *problem, void *excinfo, const double *head, int64_t n_head,
                               const double *memory, const double *wear_depth, int64_t n_points,
                               double bushing_radius, double velocity_floor, double *values);

#endif
