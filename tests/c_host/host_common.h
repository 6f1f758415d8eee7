/*
 * host_common.h -- what the C FMI hosts fmi2_host.c and fmi3_host.c share.
 *
 * One host = one process = one script run.  This part owns everything that does not depend on
 * the FMI version: the command line, the script (reading, tokenising, `expect`), the status
 * bookkeeping (names, exit codes 0/1/2, clean-up on every exit path), number parsing and
 * printing, scratch memory, the FMU-state slots, the trace loops (Co-Simulation and Model
 * Exchange), the time and resident-memory measurements, and every command that only needs
 * the calls listed in HostCall.  A host supplies those calls as thin, typed wrappers (HostOps)
 * and its own commands (HostOps.execute).
 *
 * Conventions (README.md): results on stdout (numbers %.17g), the FMU's log and the host's
 * messages on stderr; a status other than ok/warning must be acknowledged by `expect`.
 *
 * Usage: <host> [--no-unload] [--model-exchange] <fmu_dir> <model_identifier> <guid|token> <script|->
 *   --model-exchange   `instantiate`, `cycle` and `time_load` make Model Exchange instances
 *
 * Shared commands (both hosts; "fmi*X" is the host's FMI function; <slot> is 0..63)
 *   instantiate <name> [<token>]     Co-Simulation (Model Exchange with --model-exchange);
 *   instantiate_me <name> [<token>]  Model Exchange; prints "<command> ok" | "<command> null"
 *                                    (null counts as status error)
 *   free                             frees the states left in slots, then the instance
 *   enter_init | exit_init | terminate | reset | enter_event_mode | enter_continuous_time_mode
 *   | enter_config | exit_config (FMI 3.0)        prints "<command> <status>"
 *   do_step <t> <h> [<noSetFMUStatePriorToCurrentPoint, default 1>]
 *                                    prints "do_step <status>" (FMI 3.0: and its outputs)
 *   set_time <t>                     prints "set_time <status>"
 *   get_event_indicators <ni> | get_continuous_states <nx> | get_derivatives <nx>
 *                                    prints "<command> <status>", then if ok/warning one line a
 *                                    value: "indicator <i> <v>" | "x <i> <v>" | "der <i> <v>"
 *   new_discrete_states (FMI 2.0) | update_discrete_states (FMI 3.0)
 *                                    prints "<command> <status> needed=<0|1> terminate=<0|1>
 *                                    nominals_changed=.. values_changed=..
 *                                    next_event_time_defined=.. next_event_time=<t>"
 *   completed_integrator_step [<noSetFMUStatePriorToCurrentPoint, default 1>]
 *                                    prints "... <status> enter_event_mode=<0|1> terminate=<0|1>"
 *   trace <file> <n_inputs> <in_vrs|-> <out_vrs|->
 *                                    Co-Simulation: rows "t h u1..un" of <file>; a row: set the
 *                                    inputs, get the outputs, do_step(t, h).  Prints "out <t> v.."
 *                                    per row, then "trace <status> rows=<n>" or, on a failure,
 *                                    "trace <status> row=<i> call=<fmi*X>"; stderr trace_seconds
 *   trace_me <file> <n_inputs> <in_vrs|-> <out_vrs|-> [events_after|events_first]
 *                                    Model Exchange, the call sequence of wearjoint's
 *                                    core/joint_access.py at an accepted point: a row: set_time(t)
 *                                    (h is not used), set the inputs, get the outputs, get the
 *                                    (one) event indicator z, completed_integrator_step; then, if
 *                                    (z >= 0) differs from the last completed row (or the FMU asks
 *                                    for it), the event iteration: enter_event_mode, new discrete
 *                                    states until none is needed, enter_continuous_time_mode
 *                                    (events_first: the event iteration before the completed
 *                                    step).  Prints "out <t> v.." per row and
 *                                    "event <t> onset|separation|requested" after a row with an
 *                                    event, then "trace_me <status> rows=<n> events=<e> onsets=<a>
 *                                    separations=<b>" (or "row=<i> call=<fmi*X> events=..").  The
 *                                    sign at the last completed row is kept across trace_me
 *                                    commands, saved by get_state and restored by set_state;
 *                                    instantiate, reset and deserialize clear it (no contact).
 *   get_state | set_state | free_state <slot>
 *                                    prints "<command> <slot> <status>" (free_state: and
 *                                    "pointer_null=<0|1>"); an occupied slot is reused by get_state
 *   serialize <slot> <file>          prints "serialize <slot> <status> bytes=<n>"
 *   deserialize <slot> <file>        frees an occupied slot first; "deserialize <slot> <status> bytes=<n>"
 *   directional_derivative <unknown_vrs> <known_vrs> <seed,..>
 *                                    fmi*GetDirectionalDerivative (comma-separated lists; one seed a
 *                                    known, one value an unknown); prints "<command> <status>", then
 *                                    if ok/warning one line an unknown: "sensitivity <vr> <v>"
 *   cycle <n> [<name>]               n times instantiate, initialize, free (a separate instance);
 *                                    stderr rss_kb_before/rss_kb_after; "cycle <status> iterations=<k>"
 *   time_load [<name>]               instantiate + initialize (the instance stays); stderr
 *                                    startup_seconds (from main()), startup_seconds_since_exec
 *   set_debug_logging <0|1> [<category> ...]
 *   expect <status>                  the previous command returned <status> (else exit 1)
 *   echo <words...>
 */
#ifndef HOST_COMMON_H
#define HOST_COMMON_H

#include <stddef.h>

/* The FMU's binary for the machine the host was compiled for: binaries/<folder>/<id><extension>.
 * FMI 2.0 names linux64 and win64; for ARM Linux FMI 2.0.4 (section 2.3) says to use the FMI 3.0
 * platform tuple. */
#if defined(_WIN32)
#define HOST_FMI2_PLATFORM "win64"
#define HOST_FMI3_PLATFORM "x86_64-windows"
#define HOST_LIBRARY_EXTENSION ".dll"
#elif defined(__APPLE__) && defined(__aarch64__)
#define HOST_FMI2_PLATFORM "aarch64-darwin"
#define HOST_FMI3_PLATFORM "aarch64-darwin"
#define HOST_LIBRARY_EXTENSION ".dylib"
#elif defined(__APPLE__)
#define HOST_FMI2_PLATFORM "darwin64"
#define HOST_FMI3_PLATFORM "x86_64-darwin"
#define HOST_LIBRARY_EXTENSION ".dylib"
#elif defined(__aarch64__)
#define HOST_FMI2_PLATFORM "aarch64-linux"
#define HOST_FMI3_PLATFORM "aarch64-linux"
#define HOST_LIBRARY_EXTENSION ".so"
#else
#define HOST_FMI2_PLATFORM "linux64"
#define HOST_FMI3_PLATFORM "x86_64-linux"
#define HOST_LIBRARY_EXTENSION ".so"
#endif

/* MinGW checks "printf" formats against msvcrt's printf (no %zu); the hosts are built for Windows
 * with __USE_MINGW_ANSI_STDIO=1, whose printf is C99's (GNU formats). */
#if defined(__MINGW32__)
#define HOST_PRINTF_FORMAT gnu_printf
#else
#define HOST_PRINTF_FORMAT printf
#endif

#define NSLOTS 64

/* FMI statuses, numbered as fmi2Status and fmi3Status are */
enum { HOST_OK, HOST_WARNING, HOST_DISCARD, HOST_ERROR, HOST_FATAL, HOST_PENDING };

/* The FMI functions the shared code calls; HostOps.names gives each one's name in the host's FMI
 * version (NULL: that version has no such function).  Resolved from the binary by host_main. */
enum {
    CALL_INSTANTIATE_CS, CALL_INSTANTIATE_ME, CALL_FREE_INSTANCE, CALL_SET_DEBUG_LOGGING,
    CALL_SETUP_EXPERIMENT, CALL_ENTER_INIT, CALL_EXIT_INIT, CALL_TERMINATE, CALL_RESET,
    CALL_ENTER_CONFIG, CALL_EXIT_CONFIG,
    CALL_SET_REALS, CALL_GET_REALS, CALL_DO_STEP,
    CALL_SET_TIME, CALL_GET_EVENT_INDICATORS, CALL_ENTER_EVENT_MODE, CALL_NEW_DISCRETE_STATES,
    CALL_ENTER_CONTINUOUS_TIME_MODE, CALL_COMPLETED_INTEGRATOR_STEP, CALL_GET_CONTINUOUS_STATES,
    CALL_GET_DERIVATIVES,
    CALL_GET_STATE, CALL_SET_STATE, CALL_FREE_STATE, CALL_SERIALIZED_SIZE, CALL_SERIALIZE, CALL_DESERIALIZE,
    CALL_GET_DIRECTIONAL_DERIVATIVE,
    N_CALLS
};

/* fmi2EventInfo / the outputs of fmi3UpdateDiscreteStates */
typedef struct {
    int needed, terminate, nominals_changed, values_changed, next_time_defined;
    double next_time;
} HostEventInfo;

/* One FMI version, as the shared code sees it.  Every wrapper acts on H.instance (except the
 * three that take an instance) and returns the FMI status. */
typedef struct {
    const char *host;        /* program name, prefix of the host's messages: "fmi2_host" */
    const char *source;      /* where the commands are documented: "fmi2_host.c" */
    const char *token_name;  /* "guid" | "instantiation_token" (usage line) */
    const char *platform;    /* binaries/<platform>/<model_identifier><HOST_LIBRARY_EXTENSION> */
    const char *resource_prefix, *resource_suffix;   /* resource location = prefix + abs dir + suffix */
    const char *const *names;                        /* N_CALLS names */
    const char *new_discrete_states_command;         /* "new_discrete_states" | "update_discrete_states" */
    void (*load)(void);                              /* resolve the version's own functions (host_symbol) */
    void *(*instantiate)(const char *name, const char *token, int model_exchange);
    void (*free_instance)(void *instance);
    int (*call)(void *instance, int call);  /* a function of the instance alone (enter/exit_init with default
                                                arguments, setup, terminate, reset, event modes, ...) */
    int (*set_debug_logging)(int on, size_t n, const char *const categories[]);
    int (*set_reals)(const unsigned vr[], size_t n, const double v[]);
    int (*get_reals)(const unsigned vr[], size_t n, double v[]);
    int (*do_step)(double t, double h, int no_set_prior, char *report, size_t size); /* report: extra outputs */
    int (*set_time)(double t);
    int (*get_vector)(int call, double v[], size_t n); /* indicators, states, derivatives */
    int (*new_discrete_states)(HostEventInfo *info);
    int (*completed_integrator_step)(int no_set_prior, int *enter_event_mode, int *terminate);
    int (*get_state)(void **state);
    int (*set_state)(void *state);
    int (*free_state)(void **state);
    int (*serialized_size)(void *state, size_t *size);
    int (*serialize)(void *state, void *bytes, size_t size);
    int (*deserialize)(const void *bytes, size_t size, void **state);
    int (*directional_derivative)(const unsigned unknowns[], size_t n_unknowns, const unsigned knowns[],
                                  size_t n_knowns, const double seed[], double sensitivity[]);
    int (*execute)(size_t ntok);                     /* the host's own commands; 0: unknown */
} HostOps;

/* Global state of the run (one process = one script run) */
typedef struct {
    const HostOps *ops;
    void *lib;
    void *fn[N_CALLS];           /* the functions of HostCall, NULL if not exported */
    int unload;                  /* dlclose at exit (--no-unload: 0) */
    int model_exchange;          /* --model-exchange: `instantiate`, cycle, time_load use ME */
    void *instance;
    void *slots[NSLOTS];
    char *resource;              /* resource URI / path given to instantiate */
    const char *token;           /* GUID / instantiationToken from the command line */
    double t_main;               /* entry to main() */
    char **tok;                  /* the current script line, split */
    long line_no;
    int last_status, fatal_seen;
    long pending_line;           /* line of an unacknowledged failure */
    char pending_what[64];
    int me_contact;              /* trace_me: the indicator was >= 0 at the last completed step */
    int slot_contact[NSLOTS];    /* me_contact saved with the FMU state in a slot */
} Host;

extern Host H;

int host_main(int argc, char **argv, const HostOps *ops);

/* messages and exits */
void host_die2(const char *fmt, ...) __attribute__((format(HOST_PRINTF_FORMAT, 1, 2), noreturn)); /* bad input: exit 2 */
void host_die1(const char *fmt, ...) __attribute__((format(HOST_PRINTF_FORMAT, 1, 2), noreturn)); /* FMI failure: exit 1 */
void host_log(int status, const char *category, const char *message);  /* "LOG <status> <category>: <msg>" */
const char *host_status_name(int status);
int host_check(int status, const char *what);        /* record a status; a failure must be expected */
void *host_fn(int call);                             /* H.fn[call], exit 2 if the binary lacks it */
void *host_symbol(const char *name);                 /* a symbol of the FMU binary (dlsym/GetProcAddress) */
void host_need_args(size_t ntok, size_t lo, size_t hi, const char *usage);
void host_need_instance(void);
void *host_scratch(size_t n);                        /* zeroed, freed after the command or at exit */

/* parsing (exit 2 on bad input) */
double host_parse_double(const char *s, const char *what);
long long host_parse_long(const char *s, long long lo, long long hi, const char *what);
unsigned host_parse_vr(const char *s);
int host_parse_bool(const char *s);
char *host_split_assignment(char *s, unsigned *vr);   /* "vr=value" -> value */
double host_now(void);

#endif
