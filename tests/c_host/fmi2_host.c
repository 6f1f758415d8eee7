/*
 * fmi2_host.c -- a minimal, dependency-free FMI 2.0 Co-Simulation importer.
 *
 * Proves that an FMU works from C with no Python on the host (and runs under
 * valgrind).  It needs only libc and libdl:
 *
 *     gcc -O2 -Wall -Wextra -I<fmi2 headers> fmi2_host.c -o fmi2_host -ldl
 *
 * (fmpy ships the FMI 2.0 headers in <site-packages>/fmpy/c-code/.)
 *
 * Usage
 *     fmi2_host [--no-unload] <fmu_dir> <model_identifier> <guid> <script_file>
 *
 *   <fmu_dir>          an unzipped FMU; the binary loaded is
 *                      <fmu_dir>/binaries/linux64/<model_identifier>.so
 *   <script_file>      one command per line ("-" reads stdin); blank lines and
 *                      lines whose first word starts with '#' are ignored
 *   --no-unload        do not dlclose() the binary at exit
 *
 * Output
 *   stdout  results, deterministic for a deterministic FMU (status lines,
 *           values, trace rows), so two runs can be compared byte for byte
 *   stderr  the FMU's log as "LOG <status> <category>: <message>", the host's
 *           diagnostics ("fmi2_host: ...") and everything measured from the
 *           machine: trace_seconds, startup_seconds, rss_kb_before/after
 *
 *   Numbers are printed with %.17g (round-trips a double bit for bit).
 *   Status names: ok warning discard error fatal pending.
 *
 * Exit codes
 *   0  script completed
 *   1  FMI failure: a call returned discard/error/fatal/pending and the next
 *      script line was not an `expect`, or an `expect` did not match
 *   2  bad input to the host itself: usage, unreadable script / data file,
 *      syntax error, missing binary or missing fmi2 symbol, no instance
 *
 * Every FMI status is checked: a status other than ok/warning must be
 * acknowledged by an `expect <status>` on the next script line, otherwise the
 * run stops with exit code 1.  On every exit path the host frees what it
 * allocated: FMU states still held in slots (fmi2FreeFMUstate), the instance
 * (fmi2FreeInstance -- skipped once any call returned fatal), the library.
 *
 * Commands (one instance at a time; <vr> is an unsigned value reference;
 * <slot> is 0..63)
 *   instantiate <name> [<guid>]   fmi2Instantiate(fmi2CoSimulation, resource
 *                                 URI file://<abs fmu_dir>/resources,
 *                                 visible=0, loggingOn=1); <guid> overrides
 *                                 the command-line GUID.
 *                                 prints "instantiate ok" | "instantiate null"
 *                                 (null counts as status error)
 *   free                          frees the states still in slots, then
 *                                 fmi2FreeInstance; prints "free ok"
 *   setup <t0> [<stop> [<tol>]]   fmi2SetupExperiment; prints "setup <status>"
 *   enter_init | exit_init | terminate | reset
 *                                 prints "<command> <status>"
 *   set_real <vr>=<value> ...     also set_integer, set_boolean (0/1/true/
 *                                 false), set_string (value without blanks);
 *                                 prints "<command> <status>"
 *   get_real <vr> ...             also get_integer, get_boolean, get_string;
 *                                 prints "<command> <status>" and, if ok or
 *                                 warning, one line per vr:
 *                                 "real <vr> <%.17g>" | "integer <vr> <d>" |
 *                                 "boolean <vr> <0|1>" | "string <vr> <s>"
 *   do_step <t> <h> [<noSetFMUStatePriorToCurrentPoint 0|1, default 1>]
 *                                 prints "do_step <status>"
 *   trace <file> <n_inputs> <in_vrs> <out_vrs>
 *                                 <in_vrs>/<out_vrs>: comma-separated vrs, or
 *                                 "-" for none.  <file>: rows "t h u1 .. un"
 *                                 (whitespace-separated doubles, '#' comments
 *                                 and blank lines skipped), read completely
 *                                 before the loop.  For each row: set_real the
 *                                 inputs, get_real the outputs, do_step(t, h).
 *                                 Prints one line per row "out <t> v1 v2 ..."
 *                                 (the outputs at t, before the step), then
 *                                 "trace <status> rows=<n>" -- or, if a call
 *                                 failed, "trace <status> row=<i> call=<fmi2X>"
 *                                 after the rows done so far.  stderr gets
 *                                 "trace_seconds <s>": wall time of the loop
 *                                 of FMI calls only (no parsing, no printing).
 *   get_state <slot>              fmi2GetFMUstate(c, &slot) (an occupied slot
 *                                 is passed in for reuse, as FMI specifies);
 *                                 prints "get_state <slot> <status>"
 *   set_state <slot>              fmi2SetFMUstate(c, slot) (NULL if empty);
 *                                 prints "set_state <slot> <status>"
 *   free_state <slot>             fmi2FreeFMUstate(c, &slot); prints
 *                                 "free_state <slot> <status> pointer_null=<0|1>"
 *   serialize <slot> <file>       fmi2SerializedFMUstateSize + fmi2SerializeFMUstate,
 *                                 writes the bytes; prints
 *                                 "serialize <slot> <status> bytes=<n>"
 *   deserialize <slot> <file>     reads the bytes, frees an occupied slot first,
 *                                 fmi2DeSerializeFMUstate(c, .., &slot); prints
 *                                 "deserialize <slot> <status> bytes=<n>"
 *   cycle <n> [<name>]            n times: instantiate, setup 0, enter_init,
 *                                 exit_init, free (a separate instance; the
 *                                 current one, if any, is left alone).  stderr:
 *                                 "rss_kb_before <x>", "rss_kb_after <y>"
 *                                 (/proc/self/statm); stdout:
 *                                 "cycle <status> iterations=<k>".  Run a
 *                                 "cycle 1" first to exclude one-off costs.
 *   time_load [<name>]            instantiate + setup 0 + enter_init +
 *                                 exit_init (the instance stays, initialized);
 *                                 stdout "time_load <status>"; stderr
 *                                 "startup_seconds <s>" measured from entry to
 *                                 main() (before the dlopen) to the return of
 *                                 fmi2ExitInitializationMode, and
 *                                 "startup_seconds_since_exec <s>" (from the
 *                                 kernel's process start time, 1/CLK_TCK
 *                                 resolution).  Make it the first command.
 *   expect <status>               the previous FMI command returned <status>,
 *                                 else exit 1; acknowledges a failure status
 *   call_null <fmi2Function> [<what>]
 *                                 calls one function with NULL arguments and
 *                                 prints "call_null <fmi2Function> <what>
 *                                 <status>" (fmi2Instantiate: "... null" or
 *                                 "... nonnull", nonnull counts as error and
 *                                 the instance is freed).  A failure status
 *                                 here is the expected outcome: it needs no
 *                                 `expect` (but `expect` may check it).
 *                                 <what>, default "component":
 *                                   component  NULL fmi2Component, other args
 *                                              valid (every function with a
 *                                              component; fmi2FreeInstance(NULL)
 *                                              must merely not crash)
 *                                   values     NULL value array / NULL out
 *                                              pointer (fmi2Get*, fmi2Set*,
 *                                              fmi2GetFMUstate(c, NULL),
 *                                              fmi2FreeFMUstate(c, NULL),
 *                                              fmi2SerializedFMUstateSize
 *                                              size pointer, fmi2SerializeFMUstate
 *                                              and fmi2DeSerializeFMUstate
 *                                              buffer, fmi2Get*Status)
 *                                   vr         NULL value-reference array
 *                                              with nvr=1 (fmi2Get* and fmi2Set*)
 *                                   state      NULL fmi2FMUstate
 *                                              (fmi2SetFMUstate,
 *                                              fmi2SerializedFMUstateSize,
 *                                              fmi2SerializeFMUstate)
 *                                   name|guid|callbacks|logger|alloc
 *                                              for fmi2Instantiate: NULL
 *                                              instanceName / GUID / callback
 *                                              struct / logger / allocateMemory
 *                                 With values/vr/state the host's own instance
 *                                 is used (instantiate it first); value
 *                                 reference 0 and nvr=1 are passed.
 *   set_debug_logging <0|1> [<category> ...]
 *   version                       prints "version <fmi2GetVersion> <fmi2GetTypesPlatform>"
 *   echo <words...>               prints the words (a marker in stdout)
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fmi2FunctionTypes.h"

#define NSLOTS 64

/* ------------------------------------------------------------------------- */
/* FMI API resolved from the shared library                                  */

typedef struct {
    fmi2GetTypesPlatformTYPE *getTypesPlatform;
    fmi2GetVersionTYPE *getVersion;
    fmi2SetDebugLoggingTYPE *setDebugLogging;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *freeInstance;
    fmi2SetupExperimentTYPE *setupExperiment;
    fmi2EnterInitializationModeTYPE *enterInit;
    fmi2ExitInitializationModeTYPE *exitInit;
    fmi2TerminateTYPE *terminate;
    fmi2ResetTYPE *reset;
    fmi2GetRealTYPE *getReal;
    fmi2GetIntegerTYPE *getInteger;
    fmi2GetBooleanTYPE *getBoolean;
    fmi2GetStringTYPE *getString;
    fmi2SetRealTYPE *setReal;
    fmi2SetIntegerTYPE *setInteger;
    fmi2SetBooleanTYPE *setBoolean;
    fmi2SetStringTYPE *setString;
    fmi2GetFMUstateTYPE *getFMUstate;
    fmi2SetFMUstateTYPE *setFMUstate;
    fmi2FreeFMUstateTYPE *freeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *serializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *serializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *deSerializeFMUstate;
    fmi2SetRealInputDerivativesTYPE *setRealInputDerivatives;
    fmi2GetRealOutputDerivativesTYPE *getRealOutputDerivatives;
    fmi2DoStepTYPE *doStep;
    fmi2CancelStepTYPE *cancelStep;
    fmi2GetStatusTYPE *getStatus;
    fmi2GetRealStatusTYPE *getRealStatus;
    fmi2GetIntegerStatusTYPE *getIntegerStatus;
    fmi2GetBooleanStatusTYPE *getBooleanStatus;
    fmi2GetStringStatusTYPE *getStringStatus;
} Api;

/* ------------------------------------------------------------------------- */
/* Global state (one process = one script run)                               */

static Api api;
static void *lib = NULL;
static int unload = 1;
static fmi2Component comp = NULL;
static fmi2FMUstate slots[NSLOTS];
static char *resource_uri = NULL;
static const char *guid_arg = NULL;
static double t_main = 0.0;

static FILE *script = NULL;
static char *line = NULL;
static size_t line_cap = 0;
static char **tok = NULL;
static size_t tok_cap = 0;
static long line_no = 0;

/* scratch buffers owned by the command being executed; freed by cleanup() */
static void *scratch[8];

static fmi2Status last_status = fmi2OK;
static int fatal_seen = 0;
static long pending_line = 0;           /* line of an unacknowledged failure */
static char pending_what[64];

/* ------------------------------------------------------------------------- */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *status_name(fmi2Status s)
{
    switch (s) {
    case fmi2OK: return "ok";
    case fmi2Warning: return "warning";
    case fmi2Discard: return "discard";
    case fmi2Error: return "error";
    case fmi2Fatal: return "fatal";
    case fmi2Pending: return "pending";
    default: return "invalid";
    }
}

static int status_from_name(const char *name, fmi2Status *s)
{
    static const char *names[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
    for (int i = 0; i < 6; i++) {
        if (strcmp(name, names[i]) == 0) {
            *s = (fmi2Status)i;
            return 1;
        }
    }
    return 0;
}

static void free_scratch(void)
{
    for (size_t i = 0; i < sizeof scratch / sizeof scratch[0]; i++) {
        free(scratch[i]);
        scratch[i] = NULL;
    }
}

static void cleanup(void)
{
    if (comp != NULL && !fatal_seen) {
        for (int i = 0; i < NSLOTS; i++) {
            if (slots[i] != NULL && api.freeFMUstate != NULL) {
                fmi2Status s = api.freeFMUstate(comp, &slots[i]);
                if (s > fmi2Warning)
                    fprintf(stderr, "fmi2_host: cleanup: fmi2FreeFMUstate(slot %d) returned %s\n",
                            i, status_name(s));
            }
            slots[i] = NULL;
        }
        if (api.freeInstance != NULL)
            api.freeInstance(comp);
    }
    comp = NULL;
    if (lib != NULL && unload)
        dlclose(lib);
    lib = NULL;
    free_scratch();
    free(resource_uri);
    resource_uri = NULL;
    free(line);
    line = NULL;
    free(tok);
    tok = NULL;
    if (script != NULL && script != stdin)
        fclose(script);
    script = NULL;
    fflush(stdout);
}

static void finish(int code)
{
    cleanup();
    exit(code);
}

/* exit 2: bad input to the host itself */
static void die2(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
static void die2(const char *fmt, ...)
{
    va_list ap;
    fflush(stdout);
    fprintf(stderr, "fmi2_host: error: ");
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    if (line_no > 0)
        fprintf(stderr, " (script line %ld)", line_no);
    fprintf(stderr, "\n");
    finish(2);
    exit(2); /* not reached */
}

/* exit 1: FMI failure */
static void die1(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
static void die1(const char *fmt, ...)
{
    va_list ap;
    fflush(stdout);
    fprintf(stderr, "fmi2_host: FMI failure: ");
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n");
    finish(1);
    exit(1); /* not reached */
}

/* allocate a buffer freed by cleanup() or at the end of the command */
static void *scratch_alloc(size_t n)
{
    for (size_t i = 0; i < sizeof scratch / sizeof scratch[0]; i++) {
        if (scratch[i] == NULL) {
            scratch[i] = calloc(n ? n : 1, 1);
            if (scratch[i] == NULL)
                die2("out of memory (%zu bytes)", n);
            return scratch[i];
        }
    }
    die2("internal error: scratch buffers exhausted");
}

/* record the status of an FMI call; a failure must be acknowledged */
static fmi2Status check(fmi2Status s, const char *what)
{
    last_status = s;
    if (s == fmi2Fatal)
        fatal_seen = 1;
    if (s != fmi2OK && s != fmi2Warning) {
        pending_line = line_no;
        snprintf(pending_what, sizeof pending_what, "%s", what);
    }
    return s;
}

/* ------------------------------------------------------------------------- */
/* Callbacks given to the FMU                                                */

static void logger(fmi2ComponentEnvironment env, fmi2String instance_name, fmi2Status status,
                   fmi2String category, fmi2String message, ...)
{
    char small[1024];
    char *buf = small;
    va_list ap;
    int n;
    (void)env;
    (void)instance_name;
    if (message == NULL)
        message = "(null message)";
    va_start(ap, message);
    n = vsnprintf(small, sizeof small, message, ap);
    va_end(ap);
    if (n < 0) {
        snprintf(small, sizeof small, "(unformattable message: %s)", message);
    } else if ((size_t)n >= sizeof small) {
        buf = malloc((size_t)n + 1);
        if (buf != NULL) {
            va_start(ap, message);
            vsnprintf(buf, (size_t)n + 1, message, ap);
            va_end(ap);
        } else {
            buf = small; /* truncated */
        }
    }
    fprintf(stderr, "LOG %s %s: %s\n", status_name(status), category ? category : "(null)", buf);
    if (buf != small)
        free(buf);
}

static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
static const fmi2CallbackFunctions callbacks_no_logger = {NULL, calloc, free, NULL, NULL};
static const fmi2CallbackFunctions callbacks_no_alloc = {logger, NULL, free, NULL, NULL};

/* ------------------------------------------------------------------------- */
/* Parsing                                                                   */

static double parse_double(const char *s, const char *what)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE)
        die2("%s: not a number: '%s'", what, s);
    return v;
}

static long parse_long(const char *s, long lo, long hi, const char *what)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        die2("%s: not an integer in [%ld, %ld]: '%s'", what, lo, hi, s);
    return v;
}

static fmi2ValueReference parse_vr(const char *s)
{
    char *end;
    unsigned long v;
    errno = 0;
    if (s[0] == '-' || s[0] == '+')
        die2("not a value reference: '%s'", s);
    v = strtoul(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v > UINT_MAX)
        die2("not a value reference: '%s'", s);
    return (fmi2ValueReference)v;
}

static int parse_slot(const char *s)
{
    return (int)parse_long(s, 0, NSLOTS - 1, "slot");
}

static fmi2Boolean parse_bool(const char *s)
{
    if (strcmp(s, "1") == 0 || strcmp(s, "true") == 0)
        return fmi2True;
    if (strcmp(s, "0") == 0 || strcmp(s, "false") == 0)
        return fmi2False;
    die2("not a boolean (0/1/true/false): '%s'", s);
}

/* split "vr=value" in place; returns the value part */
static char *split_assignment(char *s, fmi2ValueReference *vr)
{
    char *eq = strchr(s, '=');
    if (eq == NULL || eq == s)
        die2("expected <vr>=<value>, got '%s'", s);
    *eq = '\0';
    *vr = parse_vr(s);
    return eq + 1;
}

/* comma-separated list of vrs, or "-" for none; the array is scratch */
static size_t parse_vr_list(const char *s, fmi2ValueReference **out)
{
    size_t n = 1, k = 0;
    char *copy, *p, *save = NULL;
    *out = NULL;
    if (strcmp(s, "-") == 0)
        return 0;
    for (const char *q = s; *q; q++)
        if (*q == ',')
            n++;
    *out = scratch_alloc(n * sizeof **out);
    copy = scratch_alloc(strlen(s) + 1);
    strcpy(copy, s);
    for (p = strtok_r(copy, ",", &save); p != NULL; p = strtok_r(NULL, ",", &save))
        (*out)[k++] = parse_vr(p);
    if (k != n)
        die2("bad value-reference list '%s'", s);
    return n;
}

static size_t tokenize(char *s)
{
    size_t n = 0;
    char *save = NULL;
    for (char *p = strtok_r(s, " \t\r\n", &save); p != NULL; p = strtok_r(NULL, " \t\r\n", &save)) {
        if (n + 1 >= tok_cap) {
            size_t cap = tok_cap ? 2 * tok_cap : 16;
            char **t = realloc(tok, cap * sizeof *t);
            if (t == NULL)
                die2("out of memory");
            tok = t;
            tok_cap = cap;
        }
        tok[n++] = p;
    }
    if (tok != NULL)
        tok[n] = NULL;
    return n;
}

static void need_args(size_t ntok, size_t lo, size_t hi, const char *usage)
{
    if (ntok - 1 < lo || ntok - 1 > hi)
        die2("usage: %s", usage);
}

static void need_comp(void)
{
    if (comp == NULL)
        die2("'%s' needs an instance: no successful 'instantiate' before it", tok[0]);
}

#define REQUIRE(field, name)                                                 \
    do {                                                                     \
        if (api.field == NULL)                                               \
            die2("the FMU binary does not export %s", name);                 \
    } while (0)

/* ------------------------------------------------------------------------- */
/* Commands                                                                  */

static long rss_kb(void)
{
    long size = 0, resident = -1;
    FILE *f = fopen("/proc/self/statm", "r");
    if (f == NULL)
        return -1;
    if (fscanf(f, "%ld %ld", &size, &resident) != 2)
        resident = -1;
    fclose(f);
    return resident < 0 ? -1 : resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/* seconds since the kernel started this process (1/CLK_TCK resolution) */
static double seconds_since_exec(void)
{
    char buf[4096];
    size_t n;
    char *p, *save = NULL;
    unsigned long long start_ticks = 0;
    struct timespec ts;
    FILE *f = fopen("/proc/self/stat", "r");
    if (f == NULL)
        return -1.0;
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    p = strrchr(buf, ')');
    if (p == NULL)
        return -1.0;
    /* fields after the command name start with field 3 (state); starttime is field 22 */
    p = strtok_r(p + 1, " ", &save);
    for (int field = 3; p != NULL; field++, p = strtok_r(NULL, " ", &save)) {
        if (field == 22) {
            start_ticks = strtoull(p, NULL, 10);
            break;
        }
    }
    if (p == NULL || clock_gettime(CLOCK_BOOTTIME, &ts) != 0)
        return -1.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec - (double)start_ticks / (double)sysconf(_SC_CLK_TCK);
}

static fmi2Component do_instantiate(const char *name, const char *guid)
{
    REQUIRE(instantiate, "fmi2Instantiate");
    return api.instantiate(name, fmi2CoSimulation, guid, resource_uri, &callbacks, fmi2False, fmi2True);
}

static void free_instance(void)
{
    for (int i = 0; i < NSLOTS; i++) {
        if (slots[i] != NULL) {
            REQUIRE(freeFMUstate, "fmi2FreeFMUstate");
            fprintf(stderr, "fmi2_host: note: freeing the FMU state in slot %d before fmi2FreeInstance\n", i);
            if (check(api.freeFMUstate(comp, &slots[i]), "fmi2FreeFMUstate") > fmi2Warning)
                die1("fmi2FreeFMUstate(slot %d) returned %s", i, status_name(last_status));
            slots[i] = NULL;
        }
    }
    REQUIRE(freeInstance, "fmi2FreeInstance");
    api.freeInstance(comp);
    comp = NULL;
    last_status = fmi2OK;
}

static void cmd_get(size_t ntok)
{
    size_t n = ntok - 1;
    fmi2ValueReference *vr;
    fmi2Status s;
    const char *cmd = tok[0];
    need_comp();
    if (n == 0)
        die2("usage: %s <vr> [<vr> ...]", cmd);
    vr = scratch_alloc(n * sizeof *vr);
    for (size_t i = 0; i < n; i++)
        vr[i] = parse_vr(tok[i + 1]);
    if (strcmp(cmd, "get_real") == 0) {
        fmi2Real *v = scratch_alloc(n * sizeof *v);
        REQUIRE(getReal, "fmi2GetReal");
        s = check(api.getReal(comp, vr, n, v), "fmi2GetReal");
        printf("%s %s\n", cmd, status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("real %u %.17g\n", vr[i], v[i]);
    } else if (strcmp(cmd, "get_integer") == 0) {
        fmi2Integer *v = scratch_alloc(n * sizeof *v);
        REQUIRE(getInteger, "fmi2GetInteger");
        s = check(api.getInteger(comp, vr, n, v), "fmi2GetInteger");
        printf("%s %s\n", cmd, status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("integer %u %d\n", vr[i], v[i]);
    } else if (strcmp(cmd, "get_boolean") == 0) {
        fmi2Boolean *v = scratch_alloc(n * sizeof *v);
        REQUIRE(getBoolean, "fmi2GetBoolean");
        s = check(api.getBoolean(comp, vr, n, v), "fmi2GetBoolean");
        printf("%s %s\n", cmd, status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("boolean %u %d\n", vr[i], v[i] ? 1 : 0);
    } else {
        fmi2String *v = scratch_alloc(n * sizeof *v);
        REQUIRE(getString, "fmi2GetString");
        s = check(api.getString(comp, vr, n, v), "fmi2GetString");
        printf("%s %s\n", cmd, status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("string %u %s\n", vr[i], v[i] ? v[i] : "(null)");
    }
}

static void cmd_set(size_t ntok)
{
    size_t n = ntok - 1;
    fmi2ValueReference *vr;
    fmi2Status s;
    const char *cmd = tok[0];
    need_comp();
    if (n == 0)
        die2("usage: %s <vr>=<value> [<vr>=<value> ...]", cmd);
    vr = scratch_alloc(n * sizeof *vr);
    if (strcmp(cmd, "set_real") == 0) {
        fmi2Real *v = scratch_alloc(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = parse_double(split_assignment(tok[i + 1], &vr[i]), "set_real value");
        REQUIRE(setReal, "fmi2SetReal");
        s = check(api.setReal(comp, vr, n, v), "fmi2SetReal");
    } else if (strcmp(cmd, "set_integer") == 0) {
        fmi2Integer *v = scratch_alloc(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = (fmi2Integer)parse_long(split_assignment(tok[i + 1], &vr[i]), INT_MIN, INT_MAX,
                                           "set_integer value");
        REQUIRE(setInteger, "fmi2SetInteger");
        s = check(api.setInteger(comp, vr, n, v), "fmi2SetInteger");
    } else if (strcmp(cmd, "set_boolean") == 0) {
        fmi2Boolean *v = scratch_alloc(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = parse_bool(split_assignment(tok[i + 1], &vr[i]));
        REQUIRE(setBoolean, "fmi2SetBoolean");
        s = check(api.setBoolean(comp, vr, n, v), "fmi2SetBoolean");
    } else {
        fmi2String *v = scratch_alloc(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = split_assignment(tok[i + 1], &vr[i]);
        REQUIRE(setString, "fmi2SetString");
        s = check(api.setString(comp, vr, n, v), "fmi2SetString");
    }
    printf("%s %s\n", cmd, status_name(s));
}

/* trace <file> <n_inputs> <in_vrs> <out_vrs> */
static void cmd_trace(void)
{
    const char *path = tok[1];
    size_t n_in = (size_t)parse_long(tok[2], 0, 1000000, "trace n_inputs");
    fmi2ValueReference *in_vr, *out_vr;
    size_t n_in_list = parse_vr_list(tok[3], &in_vr);
    size_t n_out = parse_vr_list(tok[4], &out_vr);
    size_t ncol = 2 + n_in, rows = 0, cap = 0, done = 0, fail_row = 0;
    double *data = NULL, *out, t0;
    char *buf = NULL;
    size_t bufcap = 0;
    long file_line = 0;
    FILE *f;
    fmi2Status s = fmi2OK, worst = fmi2OK;
    const char *failed_call = NULL;

    need_comp();
    if (n_in_list != n_in)
        die2("trace: n_inputs is %zu but %zu input value references were given", n_in, n_in_list);
    if (n_in > 0)
        REQUIRE(setReal, "fmi2SetReal");
    if (n_out > 0)
        REQUIRE(getReal, "fmi2GetReal");
    REQUIRE(doStep, "fmi2DoStep");

    f = fopen(path, "r");
    if (f == NULL)
        die2("trace: cannot open '%s': %s", path, strerror(errno));
    /* read the whole table; `data` lives in a scratch slot so every exit frees it */
    {
        size_t slot = sizeof scratch / sizeof scratch[0];
        for (size_t i = 0; i < sizeof scratch / sizeof scratch[0]; i++)
            if (scratch[i] == NULL) {
                slot = i;
                break;
            }
        if (slot == sizeof scratch / sizeof scratch[0]) {
            fclose(f);
            die2("internal error: scratch buffers exhausted");
        }
        while (getline(&buf, &bufcap, f) != -1) {
            char *p = buf, *end;
            size_t k = 0;
            file_line++;
            while (*p == ' ' || *p == '\t')
                p++;
            if (*p == '#' || *p == '\n' || *p == '\r' || *p == '\0')
                continue;
            if (rows + 1 > cap) {
                size_t ncap = cap ? 2 * cap : 1024;
                double *d = realloc(data, ncap * ncol * sizeof *d);
                if (d == NULL) {
                    free(buf);
                    fclose(f);
                    die2("out of memory reading '%s'", path);
                }
                data = d;
                scratch[slot] = d;
                cap = ncap;
            }
            for (;;) {
                while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
                    p++;
                if (*p == '\0')
                    break;
                errno = 0;
                double v = strtod(p, &end);
                if (end == p || errno == ERANGE || k >= ncol ||
                    !(*end == '\0' || *end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')) {
                    free(buf);
                    fclose(f);
                    die2("trace: %s line %ld: expected %zu numbers (t h u1..u%zu)", path, file_line,
                         ncol, n_in);
                }
                data[rows * ncol + k++] = v;
                p = end;
            }
            if (k != ncol) {
                free(buf);
                fclose(f);
                die2("trace: %s line %ld: expected %zu numbers (t h u1..u%zu), got %zu", path,
                     file_line, ncol, n_in, k);
            }
            rows++;
        }
        free(buf);
        fclose(f);
    }
    out = scratch_alloc((rows * n_out) * sizeof *out);

    t0 = now();
    for (size_t i = 0; i < rows; i++) {
        const double *row = data + i * ncol;
        if (n_in > 0) {
            s = api.setReal(comp, in_vr, n_in, row + 2);
            if (s > worst)
                worst = s;
            if (s != fmi2OK && s != fmi2Warning) {
                failed_call = "fmi2SetReal";
                fail_row = i;
                break;
            }
        }
        if (n_out > 0) {
            s = api.getReal(comp, out_vr, n_out, out + i * n_out);
            if (s > worst)
                worst = s;
            if (s != fmi2OK && s != fmi2Warning) {
                failed_call = "fmi2GetReal";
                fail_row = i;
                break;
            }
        }
        done = i + 1; /* outputs of row i are valid */
        s = api.doStep(comp, row[0], row[1], fmi2True);
        if (s > worst)
            worst = s;
        if (s != fmi2OK && s != fmi2Warning) {
            failed_call = "fmi2DoStep";
            fail_row = i;
            break;
        }
    }
    fprintf(stderr, "trace_seconds %.6f\n", now() - t0);

    for (size_t i = 0; i < done; i++) {
        printf("out %.17g", data[i * ncol]);
        for (size_t j = 0; j < n_out; j++)
            printf(" %.17g", out[i * n_out + j]);
        printf("\n");
    }
    if (failed_call != NULL) {
        check(s, failed_call);
        printf("trace %s row=%zu call=%s\n", status_name(s), fail_row, failed_call);
    } else {
        check(worst, "trace");
        printf("trace %s rows=%zu\n", status_name(worst), rows);
    }
}

static void cmd_serialize(int slot, const char *path)
{
    size_t size = 0;
    fmi2Byte *bytes;
    FILE *f;
    fmi2Status s;
    need_comp();
    REQUIRE(serializedFMUstateSize, "fmi2SerializedFMUstateSize");
    REQUIRE(serializeFMUstate, "fmi2SerializeFMUstate");
    s = check(api.serializedFMUstateSize(comp, slots[slot], &size), "fmi2SerializedFMUstateSize");
    if (s > fmi2Warning) {
        printf("serialize %d %s bytes=0\n", slot, status_name(s));
        return;
    }
    bytes = scratch_alloc(size);
    s = check(api.serializeFMUstate(comp, slots[slot], bytes, size), "fmi2SerializeFMUstate");
    printf("serialize %d %s bytes=%zu\n", slot, status_name(s), size);
    if (s > fmi2Warning)
        return;
    f = fopen(path, "wb");
    if (f == NULL)
        die2("serialize: cannot create '%s': %s", path, strerror(errno));
    if (fwrite(bytes, 1, size, f) != size) {
        fclose(f);
        die2("serialize: cannot write '%s'", path);
    }
    if (fclose(f) != 0)
        die2("serialize: cannot write '%s': %s", path, strerror(errno));
}

static void cmd_deserialize(int slot, const char *path)
{
    long len;
    size_t size;
    fmi2Byte *bytes;
    fmi2Status s;
    FILE *f;
    need_comp();
    REQUIRE(deSerializeFMUstate, "fmi2DeSerializeFMUstate");
    f = fopen(path, "rb");
    if (f == NULL)
        die2("deserialize: cannot open '%s': %s", path, strerror(errno));
    if (fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        die2("deserialize: cannot read '%s'", path);
    }
    size = (size_t)len;
    bytes = scratch_alloc(size);
    if (fread(bytes, 1, size, f) != size) {
        fclose(f);
        die2("deserialize: cannot read '%s'", path);
    }
    fclose(f);
    if (slots[slot] != NULL) {
        REQUIRE(freeFMUstate, "fmi2FreeFMUstate");
        s = check(api.freeFMUstate(comp, &slots[slot]), "fmi2FreeFMUstate");
        if (s > fmi2Warning) {
            printf("deserialize %d %s bytes=%zu\n", slot, status_name(s), size);
            return;
        }
        slots[slot] = NULL;
    }
    s = check(api.deSerializeFMUstate(comp, bytes, size, &slots[slot]), "fmi2DeSerializeFMUstate");
    printf("deserialize %d %s bytes=%zu\n", slot, status_name(s), size);
}

static void cmd_cycle(long n, const char *name)
{
    long before = rss_kb(), after, k = 0;
    fmi2Status s = fmi2OK;
    const char *failed = NULL;
    REQUIRE(setupExperiment, "fmi2SetupExperiment");
    REQUIRE(enterInit, "fmi2EnterInitializationMode");
    REQUIRE(exitInit, "fmi2ExitInitializationMode");
    REQUIRE(freeInstance, "fmi2FreeInstance");
    for (; k < n; k++) {
        fmi2Component c = do_instantiate(name, guid_arg);
        if (c == NULL) {
            s = fmi2Error;
            failed = "fmi2Instantiate";
            break;
        }
        s = api.setupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
        if (s > fmi2Warning)
            failed = "fmi2SetupExperiment";
        if (failed == NULL) {
            s = api.enterInit(c);
            if (s > fmi2Warning)
                failed = "fmi2EnterInitializationMode";
        }
        if (failed == NULL) {
            s = api.exitInit(c);
            if (s > fmi2Warning)
                failed = "fmi2ExitInitializationMode";
        }
        if (s == fmi2Fatal)
            break; /* the instance must not be touched again */
        api.freeInstance(c);
        if (failed != NULL)
            break;
    }
    after = rss_kb();
    fprintf(stderr, "rss_kb_before %ld\nrss_kb_after %ld\n", before, after);
    if (failed != NULL) {
        check(s, failed);
        printf("cycle %s iterations=%ld call=%s\n", status_name(s), k, failed);
    } else {
        check(fmi2OK, "cycle");
        printf("cycle ok iterations=%ld\n", k);
    }
}

static void cmd_time_load(const char *name)
{
    fmi2Status s;
    double t_end;
    if (comp != NULL)
        die2("time_load: an instance exists already; make time_load the first command");
    REQUIRE(setupExperiment, "fmi2SetupExperiment");
    REQUIRE(enterInit, "fmi2EnterInitializationMode");
    REQUIRE(exitInit, "fmi2ExitInitializationMode");
    comp = do_instantiate(name, guid_arg);
    if (comp == NULL) {
        check(fmi2Error, "fmi2Instantiate");
        printf("time_load error call=fmi2Instantiate\n");
        return;
    }
    s = check(api.setupExperiment(comp, fmi2False, 0.0, 0.0, fmi2False, 0.0), "fmi2SetupExperiment");
    if (s <= fmi2Warning)
        s = check(api.enterInit(comp), "fmi2EnterInitializationMode");
    if (s <= fmi2Warning)
        s = check(api.exitInit(comp), "fmi2ExitInitializationMode");
    t_end = now();
    if (s <= fmi2Warning) {
        fprintf(stderr, "startup_seconds %.6f\n", t_end - t_main);
        fprintf(stderr, "startup_seconds_since_exec %.3f\n", seconds_since_exec());
        printf("time_load %s\n", status_name(s));
    } else {
        printf("time_load %s call=%s\n", status_name(s), pending_what);
    }
}

/* call_null <function> [<what>] */
static void cmd_call_null(const char *fn, const char *what)
{
    fmi2ValueReference vr0 = 0;
    fmi2Real r = 0.0;
    fmi2Integer i = 0;
    fmi2Boolean b = fmi2False;
    fmi2String str = "";
    fmi2Status st = fmi2OK;
    fmi2FMUstate state = NULL;
    size_t size = 0;
    fmi2Byte bytes[16] = {0};
    int handled = 1;
    int is_comp = strcmp(what, "component") == 0;
    int is_values = strcmp(what, "values") == 0;
    int is_vr = strcmp(what, "vr") == 0;
    int is_state = strcmp(what, "state") == 0;
    fmi2Component c = is_comp ? NULL : comp;
    const fmi2ValueReference *vrp = is_vr ? NULL : &vr0;

    if (strcmp(fn, "fmi2Instantiate") == 0) {
        fmi2Component x = NULL;
        const char *name = "call_null", *guid = guid_arg;
        const fmi2CallbackFunctions *cb = &callbacks;
        REQUIRE(instantiate, "fmi2Instantiate");
        if (strcmp(what, "name") == 0)
            name = NULL;
        else if (strcmp(what, "guid") == 0)
            guid = NULL;
        else if (strcmp(what, "callbacks") == 0)
            cb = NULL;
        else if (strcmp(what, "logger") == 0)
            cb = &callbacks_no_logger;
        else if (strcmp(what, "alloc") == 0)
            cb = &callbacks_no_alloc;
        else
            die2("call_null fmi2Instantiate: <what> is one of name guid callbacks logger alloc");
        x = api.instantiate(name, fmi2CoSimulation, guid, resource_uri, cb, fmi2False, fmi2True);
        printf("call_null %s %s %s\n", fn, what, x == NULL ? "null" : "nonnull");
        last_status = x == NULL ? fmi2OK : fmi2Error;
        if (x != NULL && api.freeInstance != NULL)
            api.freeInstance(x);
        return;
    }
    if (!is_comp && !is_values && !is_vr && !is_state)
        die2("call_null: <what> is one of component values vr state (or, for fmi2Instantiate, "
             "name guid callbacks logger alloc), got '%s'", what);
    if (!is_comp)
        need_comp();

#define CALL(field, expr)                                                    \
    do {                                                                     \
        REQUIRE(field, fn);                                                  \
        st = (expr);                                                         \
    } while (0)
#define ONLY(cond)                                                           \
    do {                                                                     \
        if (!(cond))                                                         \
            die2("call_null: '%s' does not apply to %s", what, fn);          \
    } while (0)

    if (strcmp(fn, "fmi2FreeInstance") == 0) {
        ONLY(is_comp);
        REQUIRE(freeInstance, fn);
        api.freeInstance(NULL);
        st = fmi2OK;
    } else if (strcmp(fn, "fmi2SetDebugLogging") == 0) {
        ONLY(is_comp);
        CALL(setDebugLogging, api.setDebugLogging(c, fmi2True, 0, NULL));
    } else if (strcmp(fn, "fmi2SetupExperiment") == 0) {
        ONLY(is_comp);
        CALL(setupExperiment, api.setupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    } else if (strcmp(fn, "fmi2EnterInitializationMode") == 0) {
        ONLY(is_comp);
        CALL(enterInit, api.enterInit(c));
    } else if (strcmp(fn, "fmi2ExitInitializationMode") == 0) {
        ONLY(is_comp);
        CALL(exitInit, api.exitInit(c));
    } else if (strcmp(fn, "fmi2Terminate") == 0) {
        ONLY(is_comp);
        CALL(terminate, api.terminate(c));
    } else if (strcmp(fn, "fmi2Reset") == 0) {
        ONLY(is_comp);
        CALL(reset, api.reset(c));
    } else if (strcmp(fn, "fmi2DoStep") == 0) {
        ONLY(is_comp);
        CALL(doStep, api.doStep(c, 0.0, 1e-3, fmi2True));
    } else if (strcmp(fn, "fmi2CancelStep") == 0) {
        ONLY(is_comp);
        CALL(cancelStep, api.cancelStep(c));
    } else if (strcmp(fn, "fmi2GetReal") == 0) {
        ONLY(!is_state);
        CALL(getReal, api.getReal(c, vrp, 1, is_values ? NULL : &r));
    } else if (strcmp(fn, "fmi2GetInteger") == 0) {
        ONLY(!is_state);
        CALL(getInteger, api.getInteger(c, vrp, 1, is_values ? NULL : &i));
    } else if (strcmp(fn, "fmi2GetBoolean") == 0) {
        ONLY(!is_state);
        CALL(getBoolean, api.getBoolean(c, vrp, 1, is_values ? NULL : &b));
    } else if (strcmp(fn, "fmi2GetString") == 0) {
        ONLY(!is_state);
        CALL(getString, api.getString(c, vrp, 1, is_values ? NULL : &str));
    } else if (strcmp(fn, "fmi2SetReal") == 0) {
        ONLY(!is_state);
        CALL(setReal, api.setReal(c, vrp, 1, is_values ? NULL : &r));
    } else if (strcmp(fn, "fmi2SetInteger") == 0) {
        ONLY(!is_state);
        CALL(setInteger, api.setInteger(c, vrp, 1, is_values ? NULL : &i));
    } else if (strcmp(fn, "fmi2SetBoolean") == 0) {
        ONLY(!is_state);
        CALL(setBoolean, api.setBoolean(c, vrp, 1, is_values ? NULL : &b));
    } else if (strcmp(fn, "fmi2SetString") == 0) {
        ONLY(!is_state);
        CALL(setString, api.setString(c, vrp, 1, is_values ? NULL : &str));
    } else if (strcmp(fn, "fmi2GetFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(getFMUstate, api.getFMUstate(c, is_values ? NULL : &state));
    } else if (strcmp(fn, "fmi2SetFMUstate") == 0) {
        ONLY(is_comp || is_state);
        CALL(setFMUstate, api.setFMUstate(c, is_comp ? slots[0] : NULL));
    } else if (strcmp(fn, "fmi2FreeFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(freeFMUstate, api.freeFMUstate(c, is_values ? NULL : &state));
    } else if (strcmp(fn, "fmi2SerializedFMUstateSize") == 0) {
        ONLY(is_comp || is_values || is_state);
        CALL(serializedFMUstateSize,
             api.serializedFMUstateSize(c, is_state ? NULL : slots[0], is_values ? NULL : &size));
    } else if (strcmp(fn, "fmi2SerializeFMUstate") == 0) {
        ONLY(is_comp || is_values || is_state);
        CALL(serializeFMUstate, api.serializeFMUstate(c, is_state ? NULL : slots[0],
                                                      is_values ? NULL : bytes, sizeof bytes));
    } else if (strcmp(fn, "fmi2DeSerializeFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(deSerializeFMUstate, api.deSerializeFMUstate(c, is_values ? NULL : bytes, sizeof bytes, &state));
    } else if (strcmp(fn, "fmi2GetStatus") == 0) {
        fmi2Status v = fmi2OK;
        ONLY(is_comp || is_values);
        CALL(getStatus, api.getStatus(c, fmi2DoStepStatus, is_values ? NULL : &v));
    } else if (strcmp(fn, "fmi2GetRealStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getRealStatus, api.getRealStatus(c, fmi2LastSuccessfulTime, is_values ? NULL : &r));
    } else if (strcmp(fn, "fmi2GetIntegerStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getIntegerStatus, api.getIntegerStatus(c, fmi2DoStepStatus, is_values ? NULL : &i));
    } else if (strcmp(fn, "fmi2GetBooleanStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getBooleanStatus, api.getBooleanStatus(c, fmi2Terminated, is_values ? NULL : &b));
    } else if (strcmp(fn, "fmi2GetStringStatus") == 0) {
        ONLY(is_comp || is_values);
        CALL(getStringStatus, api.getStringStatus(c, fmi2PendingStatus, is_values ? NULL : &str));
    } else {
        handled = 0;
    }
#undef CALL
#undef ONLY
    if (!handled)
        die2("call_null: unsupported function '%s'", fn);
    /* a state the FMU returned despite the NULL argument must not leak */
    if (state != NULL && comp != NULL && api.freeFMUstate != NULL && !fatal_seen)
        api.freeFMUstate(comp, &state);
    last_status = st;
    if (st == fmi2Fatal)
        fatal_seen = 1;
    printf("call_null %s %s %s\n", fn, what, status_name(st));
}

static void execute(size_t ntok)
{
    const char *cmd = tok[0];
    fmi2Status s;

    if (strcmp(cmd, "expect") == 0) {
        fmi2Status want;
        need_args(ntok, 1, 1, "expect <ok|warning|discard|error|fatal|pending>");
        if (!status_from_name(tok[1], &want))
            die2("expect: unknown status '%s'", tok[1]);
        pending_line = 0;
        if (last_status != want)
            die1("expect %s failed at script line %ld: the previous command returned %s", tok[1],
                 line_no, status_name(last_status));
        return;
    }
    if (pending_line != 0)
        die1("%s returned %s at script line %ld and the next line is not an 'expect'", pending_what,
             status_name(last_status), pending_line);
    if (fatal_seen && strcmp(cmd, "echo") != 0)
        die2("'%s' after a fatal status: no FMI function may be called any more", cmd);

    if (strcmp(cmd, "instantiate") == 0) {
        need_args(ntok, 1, 2, "instantiate <name> [<guid>]");
        if (comp != NULL)
            die2("instantiate: an instance exists already; 'free' it first");
        comp = do_instantiate(tok[1], ntok > 2 ? tok[2] : guid_arg);
        check(comp != NULL ? fmi2OK : fmi2Error, "fmi2Instantiate");
        printf("instantiate %s\n", comp != NULL ? "ok" : "null");
    } else if (strcmp(cmd, "free") == 0) {
        need_args(ntok, 0, 0, "free");
        need_comp();
        free_instance();
        printf("free ok\n");
    } else if (strcmp(cmd, "setup") == 0) {
        double t0, stop = 0.0, tol = 0.0;
        need_args(ntok, 1, 3, "setup <t0> [<stop> [<tol>]]");
        need_comp();
        t0 = parse_double(tok[1], "setup t0");
        if (ntok > 2)
            stop = parse_double(tok[2], "setup stop");
        if (ntok > 3)
            tol = parse_double(tok[3], "setup tol");
        REQUIRE(setupExperiment, "fmi2SetupExperiment");
        s = check(api.setupExperiment(comp, ntok > 3, tol, t0, ntok > 2, stop), "fmi2SetupExperiment");
        printf("setup %s\n", status_name(s));
    } else if (strcmp(cmd, "enter_init") == 0) {
        need_args(ntok, 0, 0, "enter_init");
        need_comp();
        REQUIRE(enterInit, "fmi2EnterInitializationMode");
        s = check(api.enterInit(comp), "fmi2EnterInitializationMode");
        printf("enter_init %s\n", status_name(s));
    } else if (strcmp(cmd, "exit_init") == 0) {
        need_args(ntok, 0, 0, "exit_init");
        need_comp();
        REQUIRE(exitInit, "fmi2ExitInitializationMode");
        s = check(api.exitInit(comp), "fmi2ExitInitializationMode");
        printf("exit_init %s\n", status_name(s));
    } else if (strcmp(cmd, "terminate") == 0) {
        need_args(ntok, 0, 0, "terminate");
        need_comp();
        REQUIRE(terminate, "fmi2Terminate");
        s = check(api.terminate(comp), "fmi2Terminate");
        printf("terminate %s\n", status_name(s));
    } else if (strcmp(cmd, "reset") == 0) {
        need_args(ntok, 0, 0, "reset");
        need_comp();
        REQUIRE(reset, "fmi2Reset");
        s = check(api.reset(comp), "fmi2Reset");
        printf("reset %s\n", status_name(s));
    } else if (strcmp(cmd, "set_real") == 0 || strcmp(cmd, "set_integer") == 0 ||
               strcmp(cmd, "set_boolean") == 0 || strcmp(cmd, "set_string") == 0) {
        cmd_set(ntok);
    } else if (strcmp(cmd, "get_real") == 0 || strcmp(cmd, "get_integer") == 0 ||
               strcmp(cmd, "get_boolean") == 0 || strcmp(cmd, "get_string") == 0) {
        cmd_get(ntok);
    } else if (strcmp(cmd, "do_step") == 0) {
        double t, h;
        fmi2Boolean no_set = fmi2True;
        need_args(ntok, 2, 3, "do_step <t> <h> [<noSetFMUStatePriorToCurrentPoint 0|1>]");
        need_comp();
        t = parse_double(tok[1], "do_step t");
        h = parse_double(tok[2], "do_step h");
        if (ntok > 3)
            no_set = parse_bool(tok[3]);
        REQUIRE(doStep, "fmi2DoStep");
        s = check(api.doStep(comp, t, h, no_set), "fmi2DoStep");
        printf("do_step %s\n", status_name(s));
    } else if (strcmp(cmd, "trace") == 0) {
        need_args(ntok, 4, 4, "trace <file> <n_inputs> <in_vrs|-> <out_vrs|->");
        cmd_trace();
    } else if (strcmp(cmd, "get_state") == 0) {
        int slot;
        need_args(ntok, 1, 1, "get_state <slot>");
        need_comp();
        slot = parse_slot(tok[1]);
        REQUIRE(getFMUstate, "fmi2GetFMUstate");
        s = check(api.getFMUstate(comp, &slots[slot]), "fmi2GetFMUstate");
        printf("get_state %d %s\n", slot, status_name(s));
    } else if (strcmp(cmd, "set_state") == 0) {
        int slot;
        need_args(ntok, 1, 1, "set_state <slot>");
        need_comp();
        slot = parse_slot(tok[1]);
        REQUIRE(setFMUstate, "fmi2SetFMUstate");
        s = check(api.setFMUstate(comp, slots[slot]), "fmi2SetFMUstate");
        printf("set_state %d %s\n", slot, status_name(s));
    } else if (strcmp(cmd, "free_state") == 0) {
        int slot;
        need_args(ntok, 1, 1, "free_state <slot>");
        need_comp();
        slot = parse_slot(tok[1]);
        REQUIRE(freeFMUstate, "fmi2FreeFMUstate");
        s = check(api.freeFMUstate(comp, &slots[slot]), "fmi2FreeFMUstate");
        printf("free_state %d %s pointer_null=%d\n", slot, status_name(s), slots[slot] == NULL);
    } else if (strcmp(cmd, "serialize") == 0) {
        need_args(ntok, 2, 2, "serialize <slot> <file>");
        cmd_serialize(parse_slot(tok[1]), tok[2]);
    } else if (strcmp(cmd, "deserialize") == 0) {
        need_args(ntok, 2, 2, "deserialize <slot> <file>");
        cmd_deserialize(parse_slot(tok[1]), tok[2]);
    } else if (strcmp(cmd, "cycle") == 0) {
        need_args(ntok, 1, 2, "cycle <n> [<name>]");
        cmd_cycle(parse_long(tok[1], 0, 100000000, "cycle n"), ntok > 2 ? tok[2] : "cycle");
    } else if (strcmp(cmd, "time_load") == 0) {
        need_args(ntok, 0, 1, "time_load [<name>]");
        cmd_time_load(ntok > 1 ? tok[1] : "time_load");
    } else if (strcmp(cmd, "call_null") == 0) {
        need_args(ntok, 1, 2, "call_null <fmi2Function> [<what>]");
        cmd_call_null(tok[1], ntok > 2 ? tok[2] : "component");
    } else if (strcmp(cmd, "set_debug_logging") == 0) {
        fmi2Boolean on;
        need_args(ntok, 1, 1000000, "set_debug_logging <0|1> [<category> ...]");
        need_comp();
        on = parse_bool(tok[1]);
        REQUIRE(setDebugLogging, "fmi2SetDebugLogging");
        s = check(api.setDebugLogging(comp, on, ntok - 2, ntok > 2 ? (const fmi2String *)&tok[2] : NULL),
                  "fmi2SetDebugLogging");
        printf("set_debug_logging %s\n", status_name(s));
    } else if (strcmp(cmd, "version") == 0) {
        need_args(ntok, 0, 0, "version");
        REQUIRE(getVersion, "fmi2GetVersion");
        REQUIRE(getTypesPlatform, "fmi2GetTypesPlatform");
        {
            const char *v = api.getVersion(), *p = api.getTypesPlatform();
            printf("version %s %s\n", v ? v : "(null)", p ? p : "(null)");
        }
    } else if (strcmp(cmd, "echo") == 0) {
        for (size_t k = 1; k < ntok; k++)
            printf(k == 1 ? "%s" : " %s", tok[k]);
        printf("\n");
    } else {
        die2("unknown command '%s'", cmd);
    }
}

/* ------------------------------------------------------------------------- */

static void load(const char *fmu_dir_arg, const char *model_id)
{
    char *dir = realpath(fmu_dir_arg, NULL);
    char *so;
    size_t n;
    if (dir == NULL)
        die2("FMU directory '%s': %s", fmu_dir_arg, strerror(errno));
    n = strlen(dir) + strlen(model_id) + 64;
    so = malloc(n);
    resource_uri = malloc(n);
    if (so == NULL || resource_uri == NULL) {
        free(so);
        free(dir);
        die2("out of memory");
    }
    snprintf(so, n, "%s/binaries/linux64/%s.so", dir, model_id);
    snprintf(resource_uri, n, "file://%s/resources", dir);
    free(dir);
    lib = dlopen(so, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        const char *e = dlerror();
        fprintf(stderr, "fmi2_host: error: cannot load the FMU binary %s: %s\n", so, e ? e : "?");
        free(so);
        finish(2);
    }
    free(so);
#define LOAD(field, name) api.field = (__typeof__(api.field))dlsym(lib, name)
    LOAD(getTypesPlatform, "fmi2GetTypesPlatform");
    LOAD(getVersion, "fmi2GetVersion");
    LOAD(setDebugLogging, "fmi2SetDebugLogging");
    LOAD(instantiate, "fmi2Instantiate");
    LOAD(freeInstance, "fmi2FreeInstance");
    LOAD(setupExperiment, "fmi2SetupExperiment");
    LOAD(enterInit, "fmi2EnterInitializationMode");
    LOAD(exitInit, "fmi2ExitInitializationMode");
    LOAD(terminate, "fmi2Terminate");
    LOAD(reset, "fmi2Reset");
    LOAD(getReal, "fmi2GetReal");
    LOAD(getInteger, "fmi2GetInteger");
    LOAD(getBoolean, "fmi2GetBoolean");
    LOAD(getString, "fmi2GetString");
    LOAD(setReal, "fmi2SetReal");
    LOAD(setInteger, "fmi2SetInteger");
    LOAD(setBoolean, "fmi2SetBoolean");
    LOAD(setString, "fmi2SetString");
    LOAD(getFMUstate, "fmi2GetFMUstate");
    LOAD(setFMUstate, "fmi2SetFMUstate");
    LOAD(freeFMUstate, "fmi2FreeFMUstate");
    LOAD(serializedFMUstateSize, "fmi2SerializedFMUstateSize");
    LOAD(serializeFMUstate, "fmi2SerializeFMUstate");
    LOAD(deSerializeFMUstate, "fmi2DeSerializeFMUstate");
    LOAD(setRealInputDerivatives, "fmi2SetRealInputDerivatives");
    LOAD(getRealOutputDerivatives, "fmi2GetRealOutputDerivatives");
    LOAD(doStep, "fmi2DoStep");
    LOAD(cancelStep, "fmi2CancelStep");
    LOAD(getStatus, "fmi2GetStatus");
    LOAD(getRealStatus, "fmi2GetRealStatus");
    LOAD(getIntegerStatus, "fmi2GetIntegerStatus");
    LOAD(getBooleanStatus, "fmi2GetBooleanStatus");
    LOAD(getStringStatus, "fmi2GetStringStatus");
#undef LOAD
}

int main(int argc, char **argv)
{
    int a = 1;
    t_main = now();
    if (argc > 1 && strcmp(argv[1], "--no-unload") == 0) {
        unload = 0;
        a++;
    }
    if (argc - a != 4) {
        fprintf(stderr, "usage: %s [--no-unload] <fmu_dir> <model_identifier> <guid> <script_file|->\n"
                        "(the commands are documented at the top of fmi2_host.c)\n",
                argv[0]);
        return 2;
    }
    guid_arg = argv[a + 2];
    if (strcmp(argv[a + 3], "-") == 0) {
        script = stdin;
    } else {
        script = fopen(argv[a + 3], "r");
        if (script == NULL)
            die2("cannot open the script '%s': %s", argv[a + 3], strerror(errno));
    }
    if (strchr(argv[a + 1], '/') != NULL || argv[a + 1][0] == '\0')
        die2("bad model identifier '%s'", argv[a + 1]);
    load(argv[a], argv[a + 1]);

    while (getline(&line, &line_cap, script) != -1) {
        size_t ntok;
        line_no++;
        ntok = tokenize(line);
        if (ntok == 0 || tok[0][0] == '#')
            continue;
        execute(ntok);
        free_scratch();
    }
    if (ferror(script))
        die2("error reading the script");
    if (pending_line != 0) {
        line_no = 0;
        die1("%s returned %s at script line %ld and the script ended without an 'expect'",
             pending_what, status_name(last_status), pending_line);
    }
    finish(0);
    return 0;
}
