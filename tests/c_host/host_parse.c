/*
 * host_parse.c -- parsing, for the C FMI hosts' shared part (host_internal.h): script lines and
 * their words, numbers, value references and lists of them, slots; bad input exits 2.
 */
#define _GNU_SOURCE
#include "host_internal.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static size_t tok_cap = 0;

/* The next token of *cursor delimited by any of delims (strtok_r without the C library's). */
char *host_next_token(char **cursor, const char *delims)
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

/* One line of f into *buf (grown as needed; newline kept, NUL-terminated); -1 at the end (getline). */
long host_read_line(char **buf, size_t *cap, FILE *f)
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

int host_parse_slot(const char *s)
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
size_t host_parse_vr_list(const char *s, unsigned **out)
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
    for (p = host_next_token(&cursor, ","); p != NULL; p = host_next_token(&cursor, ","))
        (*out)[k++] = host_parse_vr(p);
    if (k != n)
        host_die2("bad value-reference list '%s'", s);
    return n;
}

size_t host_tokenize(char *s)
{
    size_t n = 0;
    char *cursor = s;
    for (char *p = host_next_token(&cursor, " \t\r\n"); p != NULL; p = host_next_token(&cursor, " \t\r\n")) {
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
