/*
 * host_internal.h -- what the files of the hosts' shared part call of each other: host_common.c
 * (the run: status, messages, exits, the script loop), host_os.c (the operating system),
 * host_parse.c (script lines and numbers), host_commands.c (the shared commands but the traces)
 * and host_trace.c (trace, trace_me).  The hosts themselves (fmi2_host.c, fmi3_host.c) use
 * host_common.h only.
 */
#ifndef HOST_INTERNAL_H
#define HOST_INTERNAL_H

#include <stdio.h>

#include "host_common.h"

/* host_common.c: the buffers of the command being executed (host_scratch; freed after it) */
#define HOST_N_SCRATCH 8
extern void *host_scratch_buffers[HOST_N_SCRATCH];

/* host_os.c: loading a library, clocks, memory, paths (POSIX or Windows) */
void *host_library_open(const char *path, char *why, size_t size);   /* NULL with the reason in why */
void *host_library_symbol(void *lib, const char *name);
void host_library_close(void *lib);
char *host_absolute_directory(const char *path);  /* malloc'ed, '/' separators; NULL with errno set */
long host_rss_kb(void);                           /* resident memory of this process [kB], -1 if unknown */
double host_seconds_since_exec(void);             /* since the OS started this process, -1 if unknown */

/* host_parse.c: script lines and their words (exit 2 on bad input) */
char *host_next_token(char **cursor, const char *delims);
long host_read_line(char **buf, size_t *cap, FILE *f);    /* -1 at the end */
size_t host_tokenize(char *s);                            /* into H.tok */
int host_parse_slot(const char *s);
size_t host_parse_vr_list(const char *s, unsigned **out); /* "vr,vr,.." or "-"; the array is scratch */

/* the shared commands: host_commands.c (all but the traces) and host_trace.c */
int host_execute_common(size_t ntok);             /* 0: not a shared command */
void host_trace(size_t ntok, int me);             /* trace, trace_me */

#endif
