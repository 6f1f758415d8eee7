/*
 * host_os.c -- the operating system, for the C FMI hosts' shared part (host_internal.h): loading
 * a library, clocks, memory, paths, the process's start (POSIX or Windows).
 */
#define _GNU_SOURCE
#include "host_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(_WIN32)
#include <windows.h>
#include <psapi.h>   /* K32GetProcessMemoryInfo: in KERNEL32 from Windows 7 on */
#else
#include <dlfcn.h>
#include <unistd.h>
#endif

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
void *host_library_open(const char *path, char *why, size_t size)
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

void *host_library_symbol(void *lib, const char *name)
{
#if defined(_WIN32)
    return (void *)GetProcAddress((HMODULE)lib, name);
#else
    return dlsym(lib, name);
#endif
}

void host_library_close(void *lib)
{
#if defined(_WIN32)
    FreeLibrary((HMODULE)lib);
#else
    dlclose(lib);
#endif
}

/* the absolute path of an existing directory (malloc'ed, '/' separators), NULL with errno set */
char *host_absolute_directory(const char *path)
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
long host_rss_kb(void)
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

/* seconds since the operating system started this process (-1 if unknown) */
double host_seconds_since_exec(void)
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
    p = host_next_token(&cursor, " ");
    for (int field = 3; p != NULL; field++, p = host_next_token(&cursor, " ")) {
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
