/*
 * host_common.c -- the part of the C FMI hosts that does not depend on the FMI version
 * (see host_common.h; the commands are documented in README.md and at the top of each host):
 * the run -- status bookkeeping, messages, exits and clean-up, loading the FMU binary, the script
 * loop.  The rest of that part: host_os.c, host_parse.c, host_commands.c, host_trace.c
 * (host_internal.h).
 */
#define _GNU_SOURCE
#include "host_internal.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(_WIN32)
#include <fcntl.h>
#include <io.h>
#endif

Host H;

static FILE *script = NULL;
static char *line = NULL;
static size_t line_cap = 0;
void *host_scratch_buffers[HOST_N_SCRATCH];   /* buffers of the command being executed */

/* ------------------------------------------------------------------------- */
/* Status bookkeeping, messages, exits                                        */

static const char *const STATUS_NAMES[] = {"ok", "warning", "discard", "error", "fatal", "pending"};

const char *host_status_name(int status)
{
    return status >= 0 && status <= HOST_PENDING ? STATUS_NAMES[status] : "invalid";
}

static int status_from_name(const char *name, int *status)
{
    for (int i = 0; i <= HOST_PENDING; i++) {
        if (strcmp(name, STATUS_NAMES[i]) == 0) {
            *status = i;
            return 1;
        }
    }
    return 0;
}

static void free_scratch(void)
{
    for (size_t i = 0; i < HOST_N_SCRATCH; i++) {
        free(host_scratch_buffers[i]);
        host_scratch_buffers[i] = NULL;
    }
}

static void cleanup(void)
{
    const HostOps *ops = H.ops;
    if (H.instance != NULL && !H.fatal_seen) {
        for (int i = 0; i < NSLOTS; i++) {
            if (H.slots[i] != NULL && H.fn[CALL_FREE_STATE] != NULL) {
                int s = ops->free_state(&H.slots[i]);
                if (s > HOST_WARNING)
                    fprintf(stderr, "%s: cleanup: %s(slot %d) returned %s\n", ops->host, ops->names[CALL_FREE_STATE],
                            i, host_status_name(s));
            }
            H.slots[i] = NULL;
        }
        if (H.fn[CALL_FREE_INSTANCE] != NULL)
            ops->free_instance(H.instance);
    }
    H.instance = NULL;
    if (H.lib != NULL && H.unload)
        host_library_close(H.lib);
    H.lib = NULL;
    free_scratch();
    free(H.resource);
    H.resource = NULL;
    free(line);
    line = NULL;
    free(H.tok);
    H.tok = NULL;
    if (script != NULL && script != stdin)
        fclose(script);
    script = NULL;
    fflush(stdout);
}

static void finish(int code) __attribute__((noreturn));
static void finish(int code)
{
    cleanup();
    exit(code);
}

/* "<host>: <label>: <message>[ (script line n)]" on stderr, then exit */
static void vdie(int code, const char *label, int with_line, const char *fmt, va_list ap) __attribute__((noreturn));
static void vdie(int code, const char *label, int with_line, const char *fmt, va_list ap)
{
    fflush(stdout);
    fprintf(stderr, "%s: %s: ", H.ops->host, label);
    vfprintf(stderr, fmt, ap);
    if (with_line && H.line_no > 0)
        fprintf(stderr, " (script line %ld)", H.line_no);
    fprintf(stderr, "\n");
    finish(code);
}

void host_die2(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vdie(2, "error", 1, fmt, ap);
}

void host_die1(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vdie(1, "FMI failure", 0, fmt, ap);
}

void host_log(int status, const char *category, const char *message)
{
    fprintf(stderr, "LOG %s %s: %s\n", host_status_name(status), category ? category : "(null)",
            message ? message : "(null message)");
}

int host_check(int status, const char *what)
{
    H.last_status = status;
    if (status == HOST_FATAL)
        H.fatal_seen = 1;
    if (status != HOST_OK && status != HOST_WARNING) {
        H.pending_line = H.line_no;
        snprintf(H.pending_what, sizeof H.pending_what, "%s", what);
    }
    return status;
}

void *host_fn(int call)
{
    const char *name = H.ops->names[call];
    if (name == NULL)
        host_die2("'%s' has no counterpart in this FMI version", H.tok ? H.tok[0] : "?");
    if (H.fn[call] == NULL)
        host_die2("the FMU binary does not export %s", name);
    return H.fn[call];
}

void *host_symbol(const char *name)
{
    return host_library_symbol(H.lib, name);
}

void *host_scratch(size_t n)
{
    for (size_t i = 0; i < HOST_N_SCRATCH; i++) {
        if (host_scratch_buffers[i] == NULL) {
            host_scratch_buffers[i] = calloc(n ? n : 1, 1);
            if (host_scratch_buffers[i] == NULL)
                host_die2("out of memory (%zu bytes)", n);
            return host_scratch_buffers[i];
        }
    }
    host_die2("internal error: scratch buffers exhausted");
}

void host_need_args(size_t ntok, size_t lo, size_t hi, const char *usage)
{
    if (ntok - 1 < lo || ntok - 1 > hi)
        host_die2("usage: %s", usage);
}

void host_need_instance(void)
{
    if (H.instance == NULL)
        host_die2("'%s' needs an instance: no successful 'instantiate' before it", H.tok[0]);
}

/* ------------------------------------------------------------------------- */
/* A script line: `expect`, else the host's own commands, else the shared ones */

static void execute(size_t ntok)
{
    const char *cmd = H.tok[0];
    if (strcmp(cmd, "expect") == 0) {
        int want;
        host_need_args(ntok, 1, 1, "expect <ok|warning|discard|error|fatal|pending>");
        if (!status_from_name(H.tok[1], &want))
            host_die2("expect: unknown status '%s'", H.tok[1]);
        H.pending_line = 0;
        if (H.last_status != want)
            host_die1("expect %s failed at script line %ld: the previous command returned %s", H.tok[1], H.line_no,
                      host_status_name(H.last_status));
        return;
    }
    if (H.pending_line != 0)
        host_die1("%s returned %s at script line %ld and the next line is not an 'expect'", H.pending_what,
                  host_status_name(H.last_status), H.pending_line);
    if (H.fatal_seen && strcmp(cmd, "echo") != 0)
        host_die2("'%s' after a fatal status: no FMI function may be called any more", cmd);
    if (!H.ops->execute(ntok) && !host_execute_common(ntok))
        host_die2("unknown command '%s'", cmd);
}

/* ------------------------------------------------------------------------- */

static void load(const char *fmu_dir_arg, const char *model_id)
{
    const HostOps *ops = H.ops;
    char *dir = host_absolute_directory(fmu_dir_arg);
    char *so, why[512];
    size_t n;
    if (dir == NULL)
        host_die2("FMU directory '%s': %s", fmu_dir_arg, strerror(errno));
    n = strlen(dir) + strlen(model_id) + strlen(ops->platform) + strlen(ops->resource_prefix) +
        strlen(ops->resource_suffix) + 64;
    so = malloc(n);
    H.resource = malloc(n);
    if (so == NULL || H.resource == NULL) {
        free(so);
        free(dir);
        host_die2("out of memory");
    }
    snprintf(so, n, "%s/binaries/%s/%s%s", dir, ops->platform, model_id, HOST_LIBRARY_EXTENSION);
    /* a file URI of a Windows path has a third slash: file:///C:/... */
    snprintf(H.resource, n, "%s%s%s%s", ops->resource_prefix, dir[0] != '/' && ops->resource_prefix[0] ? "/" : "",
             dir, ops->resource_suffix);
    free(dir);
    H.lib = host_library_open(so, why, sizeof why);
    if (H.lib == NULL) {
        fprintf(stderr, "%s: error: cannot load the FMU binary %s: %s\n", ops->host, so, why);
        free(so);
        finish(2);
    }
    free(so);
    for (int i = 0; i < N_CALLS; i++)
        H.fn[i] = ops->names[i] != NULL ? host_library_symbol(H.lib, ops->names[i]) : NULL;
    ops->load();
}

int host_main(int argc, char **argv, const HostOps *ops)
{
    int a = 1;
    H.t_main = host_now();
    H.ops = ops;
#if defined(_WIN32)
    _setmode(_fileno(stdout), _O_BINARY);   /* the same bytes as on POSIX: '\n', not "\r\n" */
    _setmode(_fileno(stderr), _O_BINARY);
#endif
    H.unload = 1;
    for (; a < argc && strncmp(argv[a], "--", 2) == 0; a++) {
        if (strcmp(argv[a], "--no-unload") == 0)
            H.unload = 0;
        else if (strcmp(argv[a], "--model-exchange") == 0)
            H.model_exchange = 1;
        else
            break;
    }
    if (argc - a != 4) {
        fprintf(stderr, "usage: %s [--no-unload] [--model-exchange] <fmu_dir> <model_identifier> <%s> "
                        "<script_file|->\n(the commands are documented at the top of %s)\n",
                argv[0], ops->token_name, ops->source);
        return 2;
    }
    H.token = argv[a + 2];
    if (strcmp(argv[a + 3], "-") == 0) {
        script = stdin;
    } else {
        script = fopen(argv[a + 3], "r");
        if (script == NULL)
            host_die2("cannot open the script '%s': %s", argv[a + 3], strerror(errno));
    }
    if (strchr(argv[a + 1], '/') != NULL || argv[a + 1][0] == '\0')
        host_die2("bad model identifier '%s'", argv[a + 1]);
    load(argv[a], argv[a + 1]);

    while (host_read_line(&line, &line_cap, script) != -1) {
        size_t ntok;
        H.line_no++;
        ntok = host_tokenize(line);
        if (ntok == 0 || H.tok[0][0] == '#')
            continue;
        execute(ntok);
        free_scratch();
    }
    if (ferror(script))
        host_die2("error reading the script");
    if (H.pending_line != 0) {
        H.line_no = 0;
        host_die1("%s returned %s at script line %ld and the script ended without an 'expect'", H.pending_what,
                  host_status_name(H.last_status), H.pending_line);
    }
    finish(0);
}
