/*
 * host_common.c -- the part of the C FMI hosts that does not depend on the FMI version
 * (see host_common.h; the commands are documented in README.md and at the top of each host).
 */
#define _GNU_SOURCE
#include "host_common.h"

#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(_WIN32)
#include <fcntl.h>
#include <io.h>
#include <windows.h>
#include <psapi.h>   /* K32GetProcessMemoryInfo: in KERNEL32 from Windows 7 on */
#else
#include <dlfcn.h>
#include <unistd.h>
#endif

#define MAX_EVENT_ITERATIONS 1000

Host H;

static FILE *script = NULL;
static char *line = NULL;
static size_t line_cap = 0;
static size_t tok_cap = 0;
static void *scratch[8];   /* buffers of the command being executed */

/* ------------------------------------------------------------------------- */
/* Status bookkeeping, messages, exits                                        */

/* ------------------------------------------------------------------------- */
/* The operating system: loading a library, clocks, memory, paths (POSIX or Windows) */

double host_now(void)
{
#if defined(_WIN32)
    LARGE_INTEGER count, frequency;
    QueryPerformanceCounter(&count);
    QueryPerformanceFrequency(&frequency);
    return (double)count.QuadPart / (double)frequency.QuadPart;
#else
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
#endif
}

/* the library at path, or NULL with the reason in why */
static void *library_open(const char *path, char *why, size_t size)
{
#if defined(_WIN32)
    void *lib = (void *)LoadLibraryA(path);
    if (lib == NULL)
        snprintf(why, size, "LoadLibrary error %lu", (unsigned long)GetLastError());
    return lib;
#else
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        const char *e = dlerror();
        snprintf(why, size, "%s", e ? e : "?");
    }
    return lib;
#endif
}

static void *library_symbol(void *lib, const char *name)
{
#if defined(_WIN32)
    return (void *)GetProcAddress((HMODULE)lib, name);
#else
    return dlsym(lib, name);
#endif
}

static void library_close(void *lib)
{
#if defined(_WIN32)
    FreeLibrary((HMODULE)lib);
#else
    dlclose(lib);
#endif
}

/* the absolute path of an existing directory (malloc'ed, '/' separators), NULL with errno set */
static char *absolute_directory(const char *path)
{
#if defined(_WIN32)
    DWORD attributes = GetFileAttributesA(path);
    char *full;
    if (attributes == INVALID_FILE_ATTRIBUTES || !(attributes & FILE_ATTRIBUTE_DIRECTORY)) {
        errno = ENOENT;
        return NULL;
    }
    full = _fullpath(NULL, path, 0);
    for (char *p = full; p != NULL && *p; p++)
        if (*p == '\\')
            *p = '/';
    return full;
#else
    return realpath(path, NULL);
#endif
}

/* resident memory of this process [kB], -1 if unknown */
static long rss_kb(void)
{
#if defined(_WIN32)
    PROCESS_MEMORY_COUNTERS counters;
    if (!K32GetProcessMemoryInfo(GetCurrentProcess(), &counters, sizeof counters))
        return -1;
    return (long)(counters.WorkingSetSize / 1024);
#else
    long size = 0, resident = -1;
    FILE *f = fopen("/proc/self/statm", "r");
    if (f == NULL)
        return -1;
    if (fscanf(f, "%ld %ld", &size, &resident) != 2)
        resident = -1;
    fclose(f);
    return resident < 0 ? -1 : resident * (sysconf(_SC_PAGESIZE) / 1024);
#endif
}

/* The next token of *cursor delimited by any of delims (strtok_r without the C library's). */
static char *next_token(char **cursor, const char *delims)
{
    char *start = *cursor + strspn(*cursor, delims), *end;
    if (*start == '\0') {
        *cursor = start;
        return NULL;
    }
    end = start + strcspn(start, delims);
    if (*end != '\0')
        *end++ = '\0';
    *cursor = end;
    return start;
}

/* seconds since the operating system started this process (-1 if unknown) */
static double seconds_since_exec(void)
{
#if defined(_WIN32)
    FILETIME created, exited, kernel, user, now;
    ULARGE_INTEGER a, b;
    if (!GetProcessTimes(GetCurrentProcess(), &created, &exited, &kernel, &user))
        return -1.0;
    GetSystemTimeAsFileTime(&now);
    a.LowPart = created.dwLowDateTime;
    a.HighPart = created.dwHighDateTime;
    b.LowPart = now.dwLowDateTime;
    b.HighPart = now.dwHighDateTime;
    return 1e-7 * (double)(b.QuadPart - a.QuadPart);
#else
    /* /proc/self/stat: starttime (field 22, clock ticks since boot) against CLOCK_BOOTTIME */
    char buf[4096];
    size_t n;
    char *p, *cursor;
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
    /* fields after the command name start with field 3 (state) */
    cursor = p + 1;
    p = next_token(&cursor, " ");
    for (int field = 3; p != NULL; field++, p = next_token(&cursor, " ")) {
        if (field == 22) {
            start_ticks = strtoull(p, NULL, 10);
            break;
        }
    }
    if (p == NULL || clock_gettime(CLOCK_BOOTTIME, &ts) != 0)
        return -1.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec - (double)start_ticks / (double)sysconf(_SC_CLK_TCK);
#endif
}

/* One line of f into *buf (grown as needed; newline kept, NUL-terminated); -1 at the end (getline). */
static long read_line(char **buf, size_t *cap, FILE *f)
{
    size_t n = 0;
    int c = EOF;
    while ((c = getc(f)) != EOF) {
        if (n + 2 > *cap) {
            size_t ncap = *cap ? 2 * *cap : 256;
            char *b = realloc(*buf, ncap);
            if (b == NULL)
                host_die2("out of memory reading a line");
            *buf = b;
            *cap = ncap;
        }
        (*buf)[n++] = (char)c;
        if (c == '\n')
            break;
    }
    if (n == 0)
        return -1;
    (*buf)[n] = '\0';
    return (long)n;
}

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
    for (size_t i = 0; i < sizeof scratch / sizeof scratch[0]; i++) {
        free(scratch[i]);
        scratch[i] = NULL;
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
        library_close(H.lib);
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
    return library_symbol(H.lib, name);
}

void *host_scratch(size_t n)
{
    for (size_t i = 0; i < sizeof scratch / sizeof scratch[0]; i++) {
        if (scratch[i] == NULL) {
            scratch[i] = calloc(n ? n : 1, 1);
            if (scratch[i] == NULL)
                host_die2("out of memory (%zu bytes)", n);
            return scratch[i];
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
/* Parsing                                                                   */

double host_parse_double(const char *s, const char *what)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE)
        host_die2("%s: not a number: '%s'", what, s);
    return v;
}

long long host_parse_long(const char *s, long long lo, long long hi, const char *what)
{
    char *end;
    long long v;
    errno = 0;
    v = strtoll(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        host_die2("%s: not an integer in [%lld, %lld]: '%s'", what, lo, hi, s);
    return v;
}

unsigned host_parse_vr(const char *s)
{
    char *end;
    unsigned long v;
    errno = 0;
    if (s[0] == '-' || s[0] == '+')
        host_die2("not a value reference: '%s'", s);
    v = strtoul(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v > UINT_MAX)
        host_die2("not a value reference: '%s'", s);
    return (unsigned)v;
}

static int parse_slot(const char *s)
{
    return (int)host_parse_long(s, 0, NSLOTS - 1, "slot");
}

int host_parse_bool(const char *s)
{
    if (strcmp(s, "1") == 0 || strcmp(s, "true") == 0)
        return 1;
    if (strcmp(s, "0") == 0 || strcmp(s, "false") == 0)
        return 0;
    host_die2("not a boolean (0/1/true/false): '%s'", s);
}

char *host_split_assignment(char *s, unsigned *vr)
{
    char *eq = strchr(s, '=');
    if (eq == NULL || eq == s)
        host_die2("expected <vr>=<value>, got '%s'", s);
    *eq = '\0';
    *vr = host_parse_vr(s);
    return eq + 1;
}

/* comma-separated list of vrs, or "-" for none; the array is scratch */
static size_t parse_vr_list(const char *s, unsigned **out)
{
    size_t n = 1, k = 0;
    char *copy, *p, *cursor;
    *out = NULL;
    if (strcmp(s, "-") == 0)
        return 0;
    for (const char *q = s; *q; q++)
        if (*q == ',')
            n++;
    *out = host_scratch(n * sizeof **out);
    copy = host_scratch(strlen(s) + 1);
    strcpy(copy, s);
    cursor = copy;
    for (p = next_token(&cursor, ","); p != NULL; p = next_token(&cursor, ","))
        (*out)[k++] = host_parse_vr(p);
    if (k != n)
        host_die2("bad value-reference list '%s'", s);
    return n;
}

static size_t tokenize(char *s)
{
    size_t n = 0;
    char *cursor = s;
    for (char *p = next_token(&cursor, " \t\r\n"); p != NULL; p = next_token(&cursor, " \t\r\n")) {
        if (n + 1 >= tok_cap) {
            size_t cap = tok_cap ? 2 * tok_cap : 16;
            char **t = realloc(H.tok, cap * sizeof *t);
            if (t == NULL)
                host_die2("out of memory");
            H.tok = t;
            tok_cap = cap;
        }
        H.tok[n++] = p;
    }
    if (H.tok != NULL)
        H.tok[n] = NULL;
    return n;
}

/* ------------------------------------------------------------------------- */
/* Measurements                                                              */

/* ------------------------------------------------------------------------- */
/* Instances                                                                 */

static int instantiate_call(int model_exchange)
{
    return model_exchange ? CALL_INSTANTIATE_ME : CALL_INSTANTIATE_CS;
}

/* the calls of instantiate .. initialized .. free exist (checked before an instance is made) */
static void require_lifecycle(int model_exchange)
{
    static const int calls[] = {CALL_SETUP_EXPERIMENT, CALL_ENTER_INIT, CALL_EXIT_INIT, CALL_FREE_INSTANCE};
    host_fn(instantiate_call(model_exchange));
    for (size_t i = 0; i < sizeof calls / sizeof calls[0]; i++)
        if (H.ops->names[calls[i]] != NULL)
            host_fn(calls[i]);
}

/* setup (FMI 2.0) + enter + exit initialization with default arguments; the status of the last
 * call made, *failed the failing call or -1 */
static int initialize(void *instance, int *failed)
{
    static const int calls[] = {CALL_SETUP_EXPERIMENT, CALL_ENTER_INIT, CALL_EXIT_INIT};
    int s = HOST_OK;
    *failed = -1;
    for (size_t i = 0; i < sizeof calls / sizeof calls[0]; i++) {
        if (H.ops->names[calls[i]] == NULL)
            continue;
        s = H.ops->call(instance, calls[i]);
        if (s > HOST_WARNING) {
            *failed = calls[i];
            break;
        }
    }
    return s;
}

static void cmd_instantiate(size_t ntok, int model_exchange)
{
    const char *cmd = H.tok[0];
    int call = instantiate_call(model_exchange);
    host_need_args(ntok, 1, 2, model_exchange ? "instantiate_me <name> [<token>]" : "instantiate <name> [<token>]");
    if (H.instance != NULL)
        host_die2("%s: an instance exists already; 'free' it first", cmd);
    host_fn(call);
    H.instance = H.ops->instantiate(H.tok[1], ntok > 2 ? H.tok[2] : H.token, model_exchange);
    H.me_contact = 0;
    host_check(H.instance != NULL ? HOST_OK : HOST_ERROR, H.ops->names[call]);
    printf("%s %s\n", cmd, H.instance != NULL ? "ok" : "null");
}

static void cmd_free(void)
{
    const char *free_state = H.ops->names[CALL_FREE_STATE];
    host_need_instance();
    for (int i = 0; i < NSLOTS; i++) {
        if (H.slots[i] != NULL) {
            host_fn(CALL_FREE_STATE);
            fprintf(stderr, "%s: note: freeing the FMU state in slot %d before %s\n", H.ops->host, i,
                    H.ops->names[CALL_FREE_INSTANCE]);
            if (host_check(H.ops->free_state(&H.slots[i]), free_state) > HOST_WARNING)
                host_die1("%s(slot %d) returned %s", free_state, i, host_status_name(H.last_status));
            H.slots[i] = NULL;
        }
    }
    host_fn(CALL_FREE_INSTANCE);
    H.ops->free_instance(H.instance);
    H.instance = NULL;
    H.last_status = HOST_OK;
    printf("free ok\n");
}

static void cmd_cycle(long n, const char *name)
{
    long before = rss_kb(), after, k = 0;
    int s = HOST_OK, failed = -1;
    require_lifecycle(H.model_exchange);
    for (; k < n; k++) {
        void *c = H.ops->instantiate(name, H.token, H.model_exchange);
        if (c == NULL) {
            s = HOST_ERROR;
            failed = instantiate_call(H.model_exchange);
            break;
        }
        s = initialize(c, &failed);
        if (s == HOST_FATAL)
            break; /* the instance must not be touched again */
        H.ops->free_instance(c);
        if (failed >= 0)
            break;
    }
    after = rss_kb();
    fprintf(stderr, "rss_kb_before %ld\nrss_kb_after %ld\n", before, after);
    if (failed >= 0) {
        host_check(s, H.ops->names[failed]);
        printf("cycle %s iterations=%ld call=%s\n", host_status_name(s), k, H.ops->names[failed]);
    } else {
        host_check(HOST_OK, "cycle");
        printf("cycle ok iterations=%ld\n", k);
    }
}

static void cmd_time_load(const char *name)
{
    int s, failed = -1, call = instantiate_call(H.model_exchange);
    double t_end;
    if (H.instance != NULL)
        host_die2("time_load: an instance exists already; make time_load the first command");
    require_lifecycle(H.model_exchange);
    H.instance = H.ops->instantiate(name, H.token, H.model_exchange);
    H.me_contact = 0;
    if (H.instance == NULL) {
        host_check(HOST_ERROR, H.ops->names[call]);
        printf("time_load error call=%s\n", H.ops->names[call]);
        return;
    }
    s = initialize(H.instance, &failed);
    t_end = host_now();
    if (failed < 0) {
        fprintf(stderr, "startup_seconds %.6f\n", t_end - H.t_main);
        fprintf(stderr, "startup_seconds_since_exec %.3f\n", seconds_since_exec());
        printf("time_load %s\n", host_status_name(s));
    } else {
        host_check(s, H.ops->names[failed]);
        printf("time_load %s call=%s\n", host_status_name(s), H.ops->names[failed]);
    }
}

/* ------------------------------------------------------------------------- */
/* FMU states                                                                */

static void cmd_state(const char *cmd, int slot)
{
    int s;
    host_need_instance();
    if (strcmp(cmd, "get_state") == 0) {
        host_fn(CALL_GET_STATE);
        s = host_check(H.ops->get_state(&H.slots[slot]), H.ops->names[CALL_GET_STATE]);
        H.slot_contact[slot] = H.me_contact;
        printf("get_state %d %s\n", slot, host_status_name(s));
    } else if (strcmp(cmd, "set_state") == 0) {
        host_fn(CALL_SET_STATE);
        s = host_check(H.ops->set_state(H.slots[slot]), H.ops->names[CALL_SET_STATE]);
        if (s <= HOST_WARNING)
            H.me_contact = H.slot_contact[slot];
        printf("set_state %d %s\n", slot, host_status_name(s));
    } else {
        host_fn(CALL_FREE_STATE);
        s = host_check(H.ops->free_state(&H.slots[slot]), H.ops->names[CALL_FREE_STATE]);
        printf("free_state %d %s pointer_null=%d\n", slot, host_status_name(s), H.slots[slot] == NULL);
    }
}

static void cmd_serialize(int slot, const char *path)
{
    size_t size = 0;
    void *bytes;
    FILE *f;
    int s;
    host_need_instance();
    host_fn(CALL_SERIALIZED_SIZE);
    host_fn(CALL_SERIALIZE);
    s = host_check(H.ops->serialized_size(H.slots[slot], &size), H.ops->names[CALL_SERIALIZED_SIZE]);
    if (s > HOST_WARNING) {
        printf("serialize %d %s bytes=0\n", slot, host_status_name(s));
        return;
    }
    bytes = host_scratch(size);
    s = host_check(H.ops->serialize(H.slots[slot], bytes, size), H.ops->names[CALL_SERIALIZE]);
    printf("serialize %d %s bytes=%zu\n", slot, host_status_name(s), size);
    if (s > HOST_WARNING)
        return;
    f = fopen(path, "wb");
    if (f == NULL)
        host_die2("serialize: cannot create '%s': %s", path, strerror(errno));
    if (fwrite(bytes, 1, size, f) != size) {
        fclose(f);
        host_die2("serialize: cannot write '%s'", path);
    }
    if (fclose(f) != 0)
        host_die2("serialize: cannot write '%s': %s", path, strerror(errno));
}

static void cmd_deserialize(int slot, const char *path)
{
    long len;
    size_t size;
    void *bytes;
    int s;
    FILE *f;
    host_need_instance();
    host_fn(CALL_DESERIALIZE);
    f = fopen(path, "rb");
    if (f == NULL)
        host_die2("deserialize: cannot open '%s': %s", path, strerror(errno));
    if (fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        host_die2("deserialize: cannot read '%s'", path);
    }
    size = (size_t)len;
    bytes = host_scratch(size);
    if (fread(bytes, 1, size, f) != size) {
        fclose(f);
        host_die2("deserialize: cannot read '%s'", path);
    }
    fclose(f);
    if (H.slots[slot] != NULL) {
        host_fn(CALL_FREE_STATE);
        s = host_check(H.ops->free_state(&H.slots[slot]), H.ops->names[CALL_FREE_STATE]);
        if (s > HOST_WARNING) {
            printf("deserialize %d %s bytes=%zu\n", slot, host_status_name(s), size);
            return;
        }
        H.slots[slot] = NULL;
    }
    s = host_check(H.ops->deserialize(bytes, size, &H.slots[slot]), H.ops->names[CALL_DESERIALIZE]);
    H.slot_contact[slot] = 0;
    printf("deserialize %d %s bytes=%zu\n", slot, host_status_name(s), size);
}

/* ------------------------------------------------------------------------- */
/* Traces                                                                    */

/* Read rows of ncol doubles ('#' comments and blank lines skipped) into a scratch buffer. */
static double *read_table(const char *cmd, const char *path, size_t ncol, size_t *rows_out)
{
    size_t slot = sizeof scratch / sizeof scratch[0], rows = 0, cap = 0;
    double *data = NULL;
    char *buf = NULL;
    size_t bufcap = 0;
    long file_line = 0;
    FILE *f;
    for (size_t i = 0; i < sizeof scratch / sizeof scratch[0]; i++)
        if (scratch[i] == NULL) {
            slot = i;
            break;
        }
    if (slot == sizeof scratch / sizeof scratch[0])
        host_die2("internal error: scratch buffers exhausted");
    f = fopen(path, "r");
    if (f == NULL)
        host_die2("%s: cannot open '%s': %s", cmd, path, strerror(errno));
    while (read_line(&buf, &bufcap, f) != -1) {
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
                host_die2("out of memory reading '%s'", path);
            }
            data = d;
            scratch[slot] = d; /* every exit frees it */
            cap = ncap;
        }
        for (;;) {
            double v;
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
                p++;
            if (*p == '\0')
                break;
            errno = 0;
            v = strtod(p, &end);
            if (end == p || errno == ERANGE || k >= ncol ||
                !(*end == '\0' || *end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')) {
                free(buf);
                fclose(f);
                host_die2("%s: %s line %ld: expected %zu numbers (t h u1..u%zu)", cmd, path, file_line, ncol,
                          ncol - 2);
            }
            data[rows * ncol + k++] = v;
            p = end;
        }
        if (k != ncol) {
            free(buf);
            fclose(f);
            host_die2("%s: %s line %ld: expected %zu numbers (t h u1..u%zu), got %zu", cmd, path, file_line, ncol,
                      ncol - 2, k);
        }
        rows++;
    }
    free(buf);
    fclose(f);
    *rows_out = rows;
    return data;
}

enum { EVENT_NONE, EVENT_ONSET, EVENT_SEPARATION, EVENT_REQUESTED };
static const char *const EVENT_NAMES[] = {"", "onset", "separation", "requested"};

typedef struct {
    size_t n_in, n_out, ncol, rows;
    unsigned *in_vr, *out_vr;
    double *data, *out;
    unsigned char *event;        /* trace_me: per row, EVENT_* */
    int events_first;            /* trace_me: the event iteration before fmi*CompletedIntegratorStep */
    /* the run */
    size_t done, fail_row;       /* rows whose outputs are valid; the row of a failure */
    int status, worst, failed;   /* the last status, the worst one, the failing call (-1: none) */
    int stuck, terminated;
    size_t events[4];
} Trace;

/* 1 if the call succeeded (ok/warning); else the failure is recorded */
static int call_ok(Trace *t, int status, int call)
{
    t->status = status;
    if (status > t->worst)
        t->worst = status;
    if (status == HOST_OK || status == HOST_WARNING)
        return 1;
    t->failed = call;
    return 0;
}

/* enter event mode, update the discrete states until none is needed, back to continuous time */
static int event_iteration(Trace *t)
{
    const HostOps *ops = H.ops;
    if (!call_ok(t, ops->call(H.instance, CALL_ENTER_EVENT_MODE), CALL_ENTER_EVENT_MODE))
        return 0;
    for (int k = 0;; k++) {
        HostEventInfo info;
        memset(&info, 0, sizeof info);
        if (!call_ok(t, ops->new_discrete_states(&info), CALL_NEW_DISCRETE_STATES))
            return 0;
        if (info.terminate) {
            t->terminated = 1;
            return 0;
        }
        if (!info.needed)
            break;
        if (k + 1 >= MAX_EVENT_ITERATIONS) {
            t->stuck = 1;
            t->status = HOST_ERROR;
            t->failed = CALL_NEW_DISCRETE_STATES;
            return 0;
        }
    }
    return call_ok(t, ops->call(H.instance, CALL_ENTER_CONTINUOUS_TIME_MODE), CALL_ENTER_CONTINUOUS_TIME_MODE);
}

/* set the inputs and read the outputs of row i; 1 on success */
static int inputs_outputs(Trace *t, size_t i)
{
    const double *row = t->data + i * t->ncol;
    if (t->n_in > 0 && !call_ok(t, H.ops->set_reals(t->in_vr, t->n_in, row + 2), CALL_SET_REALS))
        return 0;
    if (t->n_out > 0 && !call_ok(t, H.ops->get_reals(t->out_vr, t->n_out, t->out + i * t->n_out), CALL_GET_REALS))
        return 0;
    t->done = i + 1; /* outputs of row i are valid */
    return 1;
}

static int cs_row(Trace *t, size_t i)
{
    const double *row = t->data + i * t->ncol;
    return inputs_outputs(t, i) && call_ok(t, H.ops->do_step(row[0], row[1], 1, NULL, 0), CALL_DO_STEP);
}

/* Model Exchange: what wearjoint/core/joint_access.py does at an accepted point */
static int me_row(Trace *t, size_t i)
{
    const HostOps *ops = H.ops;
    double z = 0.0;
    int enter = 0, terminate = 0, contact, event;
    if (!call_ok(t, ops->set_time(t->data[i * t->ncol]), CALL_SET_TIME) || !inputs_outputs(t, i) ||
        !call_ok(t, ops->get_vector(CALL_GET_EVENT_INDICATORS, &z, 1), CALL_GET_EVENT_INDICATORS))
        return 0;
    contact = z >= 0.0;
    event = contact != H.me_contact;
    if (event && t->events_first && !event_iteration(t))
        return 0;
    if (!call_ok(t, ops->completed_integrator_step(1, &enter, &terminate), CALL_COMPLETED_INTEGRATOR_STEP))
        return 0;
    if (terminate) {
        t->terminated = 1;
        return 0;
    }
    if (((event && !t->events_first) || enter) && !event_iteration(t))
        return 0;
    if (event || enter) {
        t->event[i] = event ? (contact ? EVENT_ONSET : EVENT_SEPARATION) : EVENT_REQUESTED;
        t->events[t->event[i]]++;
        H.me_contact = contact;
    }
    return 1;
}

/* trace <file> <n_inputs> <in_vrs> <out_vrs>  |  trace_me ... [events_after|events_first] */
static void cmd_trace(size_t ntok, int me)
{
    const char *cmd = H.tok[0];
    char what[64];
    Trace t;
    size_t n_in_list;
    double t0;
    memset(&t, 0, sizeof t);
    t.failed = -1;
    snprintf(what, sizeof what, "%s n_inputs", cmd);
    t.n_in = (size_t)host_parse_long(H.tok[2], 0, 1000000, what);
    n_in_list = parse_vr_list(H.tok[3], &t.in_vr);
    t.n_out = parse_vr_list(H.tok[4], &t.out_vr);
    if (ntok > 5 && strcmp(H.tok[5], "events_first") != 0 && strcmp(H.tok[5], "events_after") != 0)
        host_die2("%s: the event order is events_after or events_first, got '%s'", cmd, H.tok[5]);
    t.events_first = ntok > 5 && strcmp(H.tok[5], "events_first") == 0;
    host_need_instance();
    if (n_in_list != t.n_in)
        host_die2("%s: n_inputs is %zu but %zu input value references were given", cmd, t.n_in, n_in_list);
    if (t.n_in > 0)
        host_fn(CALL_SET_REALS);
    if (t.n_out > 0)
        host_fn(CALL_GET_REALS);
    if (me) {
        static const int calls[] = {CALL_SET_TIME, CALL_GET_EVENT_INDICATORS, CALL_COMPLETED_INTEGRATOR_STEP,
                                    CALL_ENTER_EVENT_MODE, CALL_NEW_DISCRETE_STATES, CALL_ENTER_CONTINUOUS_TIME_MODE};
        for (size_t k = 0; k < sizeof calls / sizeof calls[0]; k++)
            host_fn(calls[k]);
    } else {
        host_fn(CALL_DO_STEP);
    }
    t.ncol = 2 + t.n_in;
    t.data = read_table(cmd, H.tok[1], t.ncol, &t.rows);
    t.out = host_scratch(t.rows * t.n_out * sizeof *t.out);
    t.event = host_scratch(t.rows);

    t0 = host_now();
    for (size_t i = 0; i < t.rows; i++) {
        if (!(me ? me_row(&t, i) : cs_row(&t, i))) {
            t.fail_row = i;
            break;
        }
    }
    fprintf(stderr, "trace_seconds %.6f\n", host_now() - t0);

    for (size_t i = 0; i < t.done; i++) {
        printf("out %.17g", t.data[i * t.ncol]);
        for (size_t j = 0; j < t.n_out; j++)
            printf(" %.17g", t.out[i * t.n_out + j]);
        printf("\n");
        if (t.event[i] != EVENT_NONE)
            printf("event %.17g %s\n", t.data[i * t.ncol], EVENT_NAMES[t.event[i]]);
    }
    if (t.stuck)
        fprintf(stderr, "%s: %s: %s still needs new discrete states after %d iterations\n", H.ops->host, cmd,
                H.ops->names[CALL_NEW_DISCRETE_STATES], MAX_EVENT_ITERATIONS);
    if (t.failed >= 0) {
        host_check(t.status, H.ops->names[t.failed]);
        printf("%s %s row=%zu call=%s", cmd, host_status_name(t.status), t.fail_row, H.ops->names[t.failed]);
    } else {
        host_check(t.worst, cmd);
        printf("%s %s rows=%zu", cmd, host_status_name(t.worst), t.terminated ? t.fail_row + 1 : t.rows);
    }
    if (me)
        printf(" events=%zu onsets=%zu separations=%zu%s", t.events[EVENT_ONSET] + t.events[EVENT_SEPARATION] +
               t.events[EVENT_REQUESTED], t.events[EVENT_ONSET], t.events[EVENT_SEPARATION],
               t.terminated ? " terminate=1" : "");
    printf("\n");
}

/* ------------------------------------------------------------------------- */
/* Model Exchange calls one at a time                                        */

/* get_event_indicators <ni>, get_continuous_states <nx>, get_derivatives <nx> */
static void cmd_get_vector(int call, const char *label, const char *count)
{
    const char *cmd = H.tok[0];
    size_t n = (size_t)host_parse_long(count, 0, 1000000, cmd);
    double *v = host_scratch(n * sizeof *v);
    int s;
    host_need_instance();
    host_fn(call);
    s = host_check(H.ops->get_vector(call, v, n), H.ops->names[call]);
    printf("%s %s\n", cmd, host_status_name(s));
    if (s <= HOST_WARNING)
        for (size_t i = 0; i < n; i++)
            printf("%s %zu %.17g\n", label, i, v[i]);
}

static void cmd_new_discrete_states(void)
{
    HostEventInfo info;
    int s;
    memset(&info, 0, sizeof info);
    host_need_instance();
    host_fn(CALL_NEW_DISCRETE_STATES);
    s = host_check(H.ops->new_discrete_states(&info), H.ops->names[CALL_NEW_DISCRETE_STATES]);
    printf("%s %s", H.tok[0], host_status_name(s));
    if (s <= HOST_WARNING)
        printf(" needed=%d terminate=%d nominals_changed=%d values_changed=%d next_event_time_defined=%d "
               "next_event_time=%.17g", info.needed, info.terminate, info.nominals_changed, info.values_changed,
               info.next_time_defined, info.next_time);
    printf("\n");
}

static void cmd_completed_integrator_step(size_t ntok)
{
    int enter = 0, terminate = 0, s;
    int no_set = ntok > 1 ? host_parse_bool(H.tok[1]) : 1;
    host_need_instance();
    host_fn(CALL_COMPLETED_INTEGRATOR_STEP);
    s = host_check(H.ops->completed_integrator_step(no_set, &enter, &terminate),
                   H.ops->names[CALL_COMPLETED_INTEGRATOR_STEP]);
    printf("completed_integrator_step %s", host_status_name(s));
    if (s <= HOST_WARNING)
        printf(" enter_event_mode=%d terminate=%d", enter, terminate);
    printf("\n");
}

/* directional_derivative <unknown_vrs> <known_vrs> <seed,..> */
static void cmd_directional_derivative(void)
{
    unsigned *unknowns, *knowns;
    size_t n_unknowns = parse_vr_list(H.tok[1], &unknowns), n_knowns = parse_vr_list(H.tok[2], &knowns), k = 0;
    double *seed = host_scratch((n_knowns + 1) * sizeof *seed);
    double *sensitivity = host_scratch((n_unknowns + 1) * sizeof *sensitivity);
    char *cursor = strcmp(H.tok[3], "-") == 0 ? "" : H.tok[3];
    int s;
    for (char *p = next_token(&cursor, ","); p != NULL; p = next_token(&cursor, ",")) {
        if (k == n_knowns)
            host_die2("directional_derivative: more seed values than the %zu knowns", n_knowns);
        seed[k++] = host_parse_double(p, "seed");
    }
    if (k != n_knowns)
        host_die2("directional_derivative: %zu seed values for %zu knowns", k, n_knowns);
    host_need_instance();
    host_fn(CALL_GET_DIRECTIONAL_DERIVATIVE);
    s = host_check(H.ops->directional_derivative(unknowns, n_unknowns, knowns, n_knowns, seed, sensitivity),
                   H.ops->names[CALL_GET_DIRECTIONAL_DERIVATIVE]);
    printf("directional_derivative %s\n", host_status_name(s));
    if (s <= HOST_WARNING)
        for (size_t i = 0; i < n_unknowns; i++)
            printf("sensitivity %u %.17g\n", unknowns[i], sensitivity[i]);
}

/* ------------------------------------------------------------------------- */
/* Dispatch                                                                  */

/* commands that call one function of the instance alone: "<command> <status>" */
static const struct {
    const char *command;
    int call;
} INSTANCE_CALLS[] = {
    {"enter_init", CALL_ENTER_INIT}, {"exit_init", CALL_EXIT_INIT}, {"terminate", CALL_TERMINATE},
    {"reset", CALL_RESET}, {"enter_config", CALL_ENTER_CONFIG}, {"exit_config", CALL_EXIT_CONFIG},
    {"enter_event_mode", CALL_ENTER_EVENT_MODE}, {"enter_continuous_time_mode", CALL_ENTER_CONTINUOUS_TIME_MODE},
};

static int execute_common(size_t ntok)
{
    const char *cmd = H.tok[0];
    const HostOps *ops = H.ops;
    int s;

    for (size_t i = 0; i < sizeof INSTANCE_CALLS / sizeof INSTANCE_CALLS[0]; i++) {
        int call = INSTANCE_CALLS[i].call;
        if (strcmp(cmd, INSTANCE_CALLS[i].command) != 0 || ops->names[call] == NULL)
            continue;
        host_need_args(ntok, 0, 0, cmd);
        host_need_instance();
        host_fn(call);
        s = host_check(ops->call(H.instance, call), ops->names[call]);
        if (call == CALL_RESET)
            H.me_contact = 0;
        printf("%s %s\n", cmd, host_status_name(s));
        return 1;
    }
    if (strcmp(cmd, "instantiate") == 0 || strcmp(cmd, "instantiate_me") == 0) {
        cmd_instantiate(ntok, strcmp(cmd, "instantiate_me") == 0 || H.model_exchange);
    } else if (strcmp(cmd, "free") == 0) {
        host_need_args(ntok, 0, 0, "free");
        cmd_free();
    } else if (strcmp(cmd, "do_step") == 0) {
        double t, h;
        int no_set = 1;
        char report[256] = "";
        host_need_args(ntok, 2, 3, "do_step <t> <h> [<noSetFMUStatePriorToCurrentPoint 0|1>]");
        host_need_instance();
        t = host_parse_double(H.tok[1], "do_step t");
        h = host_parse_double(H.tok[2], "do_step h");
        if (ntok > 3)
            no_set = host_parse_bool(H.tok[3]);
        host_fn(CALL_DO_STEP);
        s = host_check(ops->do_step(t, h, no_set, report, sizeof report), ops->names[CALL_DO_STEP]);
        printf("do_step %s%s\n", host_status_name(s), report);
    } else if (strcmp(cmd, "trace") == 0 || strcmp(cmd, "trace_me") == 0) {
        int me = strcmp(cmd, "trace_me") == 0;
        host_need_args(ntok, 4, me ? 5 : 4,
                       me ? "trace_me <file> <n_inputs> <in_vrs|-> <out_vrs|-> [events_after|events_first]"
                          : "trace <file> <n_inputs> <in_vrs|-> <out_vrs|->");
        cmd_trace(ntok, me);
    } else if (strcmp(cmd, "set_time") == 0) {
        double t;
        host_need_args(ntok, 1, 1, "set_time <t>");
        host_need_instance();
        t = host_parse_double(H.tok[1], "set_time t");
        host_fn(CALL_SET_TIME);
        s = host_check(ops->set_time(t), ops->names[CALL_SET_TIME]);
        printf("set_time %s\n", host_status_name(s));
    } else if (strcmp(cmd, "get_event_indicators") == 0) {
        host_need_args(ntok, 1, 1, "get_event_indicators <ni>");
        cmd_get_vector(CALL_GET_EVENT_INDICATORS, "indicator", H.tok[1]);
    } else if (strcmp(cmd, "get_continuous_states") == 0) {
        host_need_args(ntok, 1, 1, "get_continuous_states <nx>");
        cmd_get_vector(CALL_GET_CONTINUOUS_STATES, "x", H.tok[1]);
    } else if (strcmp(cmd, "get_derivatives") == 0) {
        host_need_args(ntok, 1, 1, "get_derivatives <nx>");
        cmd_get_vector(CALL_GET_DERIVATIVES, "der", H.tok[1]);
    } else if (strcmp(cmd, ops->new_discrete_states_command) == 0) {
        host_need_args(ntok, 0, 0, cmd);
        cmd_new_discrete_states();
    } else if (strcmp(cmd, "completed_integrator_step") == 0) {
        host_need_args(ntok, 0, 1, "completed_integrator_step [<noSetFMUStatePriorToCurrentPoint 0|1>]");
        cmd_completed_integrator_step(ntok);
    } else if (strcmp(cmd, "get_state") == 0 || strcmp(cmd, "set_state") == 0 || strcmp(cmd, "free_state") == 0) {
        char usage[32];
        snprintf(usage, sizeof usage, "%s <slot>", cmd);
        host_need_args(ntok, 1, 1, usage);
        cmd_state(cmd, parse_slot(H.tok[1]));
    } else if (strcmp(cmd, "serialize") == 0) {
        host_need_args(ntok, 2, 2, "serialize <slot> <file>");
        cmd_serialize(parse_slot(H.tok[1]), H.tok[2]);
    } else if (strcmp(cmd, "deserialize") == 0) {
        host_need_args(ntok, 2, 2, "deserialize <slot> <file>");
        cmd_deserialize(parse_slot(H.tok[1]), H.tok[2]);
    } else if (strcmp(cmd, "directional_derivative") == 0) {
        host_need_args(ntok, 3, 3, "directional_derivative <unknown_vrs> <known_vrs> <seed,..>");
        cmd_directional_derivative();
    } else if (strcmp(cmd, "cycle") == 0) {
        host_need_args(ntok, 1, 2, "cycle <n> [<name>]");
        cmd_cycle(host_parse_long(H.tok[1], 0, 100000000, "cycle n"), ntok > 2 ? H.tok[2] : "cycle");
    } else if (strcmp(cmd, "time_load") == 0) {
        host_need_args(ntok, 0, 1, "time_load [<name>]");
        cmd_time_load(ntok > 1 ? H.tok[1] : "time_load");
    } else if (strcmp(cmd, "set_debug_logging") == 0) {
        int on;
        host_need_args(ntok, 1, 1000000, "set_debug_logging <0|1> [<category> ...]");
        host_need_instance();
        on = host_parse_bool(H.tok[1]);
        host_fn(CALL_SET_DEBUG_LOGGING);
        s = host_check(ops->set_debug_logging(on, ntok - 2, ntok > 2 ? (const char *const *)&H.tok[2] : NULL),
                       ops->names[CALL_SET_DEBUG_LOGGING]);
        printf("set_debug_logging %s\n", host_status_name(s));
    } else if (strcmp(cmd, "echo") == 0) {
        for (size_t k = 1; k < ntok; k++)
            printf(k == 1 ? "%s" : " %s", H.tok[k]);
        printf("\n");
    } else {
        return 0;
    }
    return 1;
}

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
    if (!H.ops->execute(ntok) && !execute_common(ntok))
        host_die2("unknown command '%s'", cmd);
}

/* ------------------------------------------------------------------------- */

static void load(const char *fmu_dir_arg, const char *model_id)
{
    const HostOps *ops = H.ops;
    char *dir = absolute_directory(fmu_dir_arg);
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
    H.lib = library_open(so, why, sizeof why);
    if (H.lib == NULL) {
        fprintf(stderr, "%s: error: cannot load the FMU binary %s: %s\n", ops->host, so, why);
        free(so);
        finish(2);
    }
    free(so);
    for (int i = 0; i < N_CALLS; i++)
        H.fn[i] = ops->names[i] != NULL ? library_symbol(H.lib, ops->names[i]) : NULL;
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

    while (read_line(&line, &line_cap, script) != -1) {
        size_t ntok;
        H.line_no++;
        ntok = tokenize(line);
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
