/* The model interface of the native FMUs: what the generic FMI layers (fmi2Functions.c,
 * fmi3Functions.c) call, and what each model implements (joint_model.c: ClearanceWearJoint;
 * slider_crank_model.c: SliderCrank).  One binary holds one model, so the functions have fixed
 * names, as the Modelica Reference-FMUs' model.c files implement one interface for their shared
 * FMI layers.
 *
 * The FMI layers own the call sequence (modes), the host's callbacks and the FMU-state objects;
 * a model owns its memory, variables, parameters (checked against its generated table,
 * model_variables.h), the calls into its compiled kernels and its state bytes.  Value
 * references are the FMI version's own (``fmi_version`` 2 or 3).  Statuses are numbered as
 * fmi2Status and fmi3Status (0 ok .. 4 fatal).  A model never prints: every message goes to
 * the host's logger through fmu_log.
 *
 * The generated model_variables.h of each model defines MODEL_GUID (the FMI 2.0 guid and FMI 3.0
 * instantiation token), N_CONTINUOUS_STATES and N_EVENT_INDICATORS.
 */
#ifndef WEARJOINT_FMU_MODEL_H
#define WEARJOINT_FMU_MODEL_H

#include <stddef.h>
#include <stdint.h>

enum { FMU_OK = 0, FMU_WARNING = 1, FMU_DISCARD = 2, FMU_ERROR = 3, FMU_FATAL = 4 };

/* The host's logger, given a complete message ('%' not escaped). */
typedef void FmuLogFunction(void *environment, const char *instance_name, int status, const char *category,
                            const char *message);
/* The host's memory functions (``environment`` is the FMI layer's). */
typedef void *FmuAllocateFunction(void *environment, size_t n, size_t size); /* zero-filled, like calloc */
typedef void FmuReleaseFunction(void *environment, void *p);

/* How a model reaches its host. */
typedef struct {
    FmuLogFunction *log;
    FmuAllocateFunction *allocate;
    FmuReleaseFunction *release;
    void *environment;   /* the FMI layer's, passed to the three functions above */
    char *name;          /* the instance name (a copy, fmu_new_instance) */
    unsigned log_categories;   /* FMU_LOG_* bits: the categories logged (errors always are) */
    int warnings_silenced;     /* the host switched logStatusWarning off (fmuSetDebugLogging): no returned warning */
} FmuHost;

/* modelDescription's <LogCategories> (fmu/model_description.py LOG_CATEGORIES) as bits: a message below FMU_ERROR
 * is logged when its category's bit is set (fmuSetDebugLogging); errors always are. */
enum { FMU_LOG_WARNINGS = 1, FMU_LOG_OTHERS = 2, FMU_LOG_ERRORS = 4, FMU_LOG_EVERY = 7 };

/* MinGW checks "printf" formats against msvcrt's printf, which knows no %zu; the FMU is built with
 * __USE_MINGW_ANSI_STDIO=1 (C99 printf from libmingwex), whose formats are GNU printf's. */
#if defined(__MINGW32__)
#if !defined(__USE_MINGW_ANSI_STDIO) || !__USE_MINGW_ANSI_STDIO
#error "build the FMU for Windows with -D__USE_MINGW_ANSI_STDIO=1 (C99 printf: the log messages use %zu)"
#endif
#define FMU_PRINTF_FORMAT gnu_printf
#else
#define FMU_PRINTF_FORMAT printf
#endif

/* ``size`` zero-filled bytes from the host whose first member is an FmuHost, filled in (the name
 * copied); NULL (logged) without memory. */
void *fmu_new_instance(size_t size, const char *name, int logging_on, FmuLogFunction *log,
                       FmuAllocateFunction *allocate, FmuReleaseFunction *release, void *environment);
/* Release an instance of fmu_new_instance (what it owns besides is released before). */
void fmu_free_instance(void *instance);
void fmu_log(const FmuHost *host, int status, const char *format, ...) __attribute__((format(FMU_PRINTF_FORMAT, 3, 4)));
/* The message of a call that returns a warning: logged with logging off too, unless the host switched
 * logStatusWarning off (a call returning fmi2Warning has called the logger, FMI 2.0 §2.1.3; fmusim, which stops at a
 * warning, had ended a run with an empty log). */
void fmu_log_returned_warning(const FmuHost *host, const char *format, ...)
    __attribute__((format(FMU_PRINTF_FORMAT, 2, 3)));
/* fmi2/fmi3SetDebugLogging: ``logging_on`` for the ``n`` categories named (every category where n is 0); with
 * ``only_these`` (FMI 2.0's loggingOn with categories) the others off.  0 (logged, nothing changed) where a name is
 * not a category of the model description. */
int fmu_set_debug_logging(FmuHost *host, int logging_on, size_t n, const char *const categories[], int only_these,
                          const char *function);
/* The shortest text that reads back as exactly x, written as Python's repr writes floats. */
const char *fmu_shortest(double x, char *out, size_t size);
/* The message of a problem a state check found (core/state_format.py): ``format``, one of the
 * generated STATE_PROBLEMS, with values[i] as text of kinds[i] (d: integer, g: shortest float, x: hex). */
const char *fmu_state_problem(const char *format, const char *kinds, const double *values, char *out, size_t size);

/* A parameter's allowed values, as the generated tables (model_variables.h) give them. */
typedef struct {
    const char *name;
    int slot;            /* index in the kernels' parameter vector */
    double start;
    int n_choices;       /* > 0: an Integer enumeration 0 .. n_choices - 1 */
    int has_low, low_open;
    double low;
    int has_high, high_open;
    double high;
    int above;           /* index of a parameter this one must exceed, or -1 */
    int when[2];         /* indices of parameters whose value when_value requires this one to be equal, or -1 */
    double when_value[2], equal;
    const char *allowed; /* the rule as the error message states it */
} ParameterInfo;

/* 1 if every value is allowed by ``table``; else logs the first that is not (name, value,
 * allowed range), prefixed by ``when``, and returns 0. */
int fmu_parameters_valid(const FmuHost *host, const ParameterInfo *table, int n, const double *values,
                         const char *when);

/* ------------------------------------------------------------------ the interface a model implements */
typedef struct FmuModel FmuModel;

/* An instance with its start values; NULL (logged) without memory. */
FmuModel *model_new(const char *name, int logging_on, FmuLogFunction *log, FmuAllocateFunction *allocate,
                    FmuReleaseFunction *release, void *environment);
void model_free(FmuModel *model);
FmuHost *model_host(FmuModel *model);
/* Every variable back to its start value (structural parameters too); 0 (logged) on failure. */
int model_reset(FmuModel *model);

double model_time(const FmuModel *model);
/* The start time (finite: the FMI layer checked it). */
void model_set_start_time(FmuModel *model, double time);
/* Check and fix the parameters; 0 (logged, naming the first bad one) if one is not allowed. */
int model_exit_initialization(FmuModel *model, const char *function);

/* Values.  Gets and sets return 1 on success, 0 on a failure they logged, -1 if ``vr`` is not a
 * variable of the type (the FMI layer says so, naming it with model_variable_name); sets -2 for a
 * parameter set after initialisation (``parameters_settable`` 0). */
void model_variable_name(const FmuModel *model, int fmi_version, unsigned vr, char *out, size_t size);
/* The number of values of the Real / Float64 variable ``vr`` (an FMI 3.0 array: its size); 0 if none. */
size_t model_float64_count(const FmuModel *model, int fmi_version, unsigned vr);
/* The sizes of the FMI 3.0 array variables for a message, e.g. " (wear_depth has n_points=1257)"; "" if none. */
const char *model_array_sizes(const FmuModel *model, char *out, size_t size);
int model_get_float64(FmuModel *model, int fmi_version, unsigned vr, double *values, const char *function);
int model_set_float64(FmuModel *model, int fmi_version, unsigned vr, double value, int parameters_settable,
                      const char *function);
/* FMI 2.0 Integer, FMI 3.0 Int64 (enumerations). */
int model_get_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t *value, const char *function);
int model_set_integer(FmuModel *model, int fmi_version, unsigned vr, int64_t value, int parameters_settable,
                      const char *function);
/* FMI 3.0 structural parameters (UInt64): set in Configuration Mode (``configuration``), or to their
 * current value where variables are ``settable``; ``state`` names the FMI state for messages. */
int model_get_structural(FmuModel *model, unsigned vr, int configuration, uint64_t *value);
int model_set_structural(FmuModel *model, unsigned vr, uint64_t value, int configuration, int settable,
                         const char *state, const char *function);
void model_enter_configuration(FmuModel *model);
/* Apply the structural parameters set in Configuration Mode; 0 (logged) on failure. */
int model_exit_configuration(FmuModel *model);

/* Directional derivatives (fmi2GetDirectionalDerivative, fmi3GetDirectionalDerivative): sensitivity = J seed, J
 * the partial derivatives of the ``unknowns`` (their values in order, an FMI 3.0 array counting its size) with
 * respect to the ``knowns`` (one value each).  1, 0 on a failure it logged (a value reference that is not an
 * output, or not an input, is named), -1 if the model provides no directional derivatives (the FMI layer says so). */
int model_directional_derivative(FmuModel *model, int fmi_version, const unsigned *unknowns, size_t n_unknowns,
                                 const unsigned *knowns, size_t n_knowns, const double *seed, double *sensitivity,
                                 const char *function);

/* Co-Simulation: advance from t over h with the inputs held; an FMU_* status (the model's
 * state and time unchanged unless FMU_OK or FMU_WARNING, time t + h then). */
int model_do_step(FmuModel *model, double t, double h, const char *function);

/* Model Exchange (N_CONTINUOUS_STATES states, N_EVENT_INDICATORS indicators); 1, or 0 logged. */
int model_set_time(FmuModel *model, double time, const char *function);
int model_get_continuous_states(FmuModel *model, double *x, const char *function);
int model_set_continuous_states(FmuModel *model, const double *x, const char *function);
int model_get_derivatives(FmuModel *model, double *dx, const char *function);
int model_get_event_indicators(FmuModel *model, double *z, const char *function);
/* An event (fmi2NewDiscreteStates, fmi3UpdateDiscreteStates). */
int model_event_update(FmuModel *model, const char *function);
/* An FMU_* status. */
int model_completed_integrator_step(FmuModel *model, const char *function);

/* FMU state.  In memory: model_state_size bytes of doubles that the model fills and reads back as they
 * are (no checks: a host gives back what it got).  Serialised: the state format (core/state_format.py:
 * header, CRC-32C), written from an in-memory state; model_deserialize_state runs every check of the
 * format and of the values (the first problem logged, 0 returned) and writes the in-memory state,
 * which it may have filled in part on failure. */
size_t model_state_size(const FmuModel *model);
void model_get_state(const FmuModel *model, double *state, int initialised);
/* Restore an in-memory state; *initialised is its flag.  0 (logged) on failure. */
int model_set_state(FmuModel *model, const double *state, int *initialised, const char *function);
size_t model_serialized_state_size(const FmuModel *model, const double *state);
void model_serialize_state(const FmuModel *model, const double *state, unsigned char *bytes);
int model_deserialize_state(FmuModel *model, const unsigned char *bytes, size_t size, double *state,
                            const char *function);

/* ------------------------------------------------------------------ FMU states (fmu_state.c, both FMI layers)
 * The fmi2/fmi3 FMU-state functions on the model's in-memory and serialised forms: FMU_OK or FMU_ERROR
 * (logged, naming ``function``).  get overwrites *state if given (it must be of this model's size),
 * else allocates one with the host's memory functions; deserialize changes a given *state only if the
 * bytes pass every check. */
int fmu_get_state(FmuModel *model, void **state, int initialised, const char *function);
int fmu_set_state(FmuModel *model, const void *state, int *initialised, const char *function);
int fmu_free_state(FmuModel *model, void **state, const char *function);
int fmu_serialized_state_size(FmuModel *model, const void *state, size_t *size, const char *function);
int fmu_serialize_state(FmuModel *model, const void *state, unsigned char *bytes, size_t size, const char *function);
int fmu_deserialize_state(FmuModel *model, const unsigned char *bytes, size_t size, void **state,
                          const char *function);

#endif
