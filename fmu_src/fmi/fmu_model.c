/* What every model of the native FMUs shares: the host (logger, memory), number formatting and
 * the parameter checks against a generated table (see fmu_model.h). */
#include "fmu_model.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void *fmu_new_instance(size_t size, const char *name, int logging_on, FmuLogFunction *log,
                       FmuAllocateFunction *allocate, FmuReleaseFunction *release, void *environment)
{
    FmuHost *host = allocate(environment, 1, size);
    char *copy = allocate(environment, strlen(name) + 1, 1);
    if (host == NULL || copy == NULL) {
        log(environment, name, FMU_ERROR, "logStatusError", "fmiInstantiate: out of memory");
        if (host != NULL)
            release(environment, host);
        if (copy != NULL)
            release(environment, copy);
        return NULL;
    }
    memset(host, 0, size);
    strcpy(copy, name);
    host->name = copy;
    host->log = log;
    host->allocate = allocate;
    host->release = release;
    host->environment = environment;
    host->log_categories = logging_on ? FMU_LOG_EVERY : 0u;
    return host;
}

void fmu_free_instance(void *instance)
{
    FmuHost host = *(FmuHost *)instance;
    host.release(host.environment, host.name);
    host.release(host.environment, instance);
}

/* the names of the FMU_LOG_* bits, lowest first */
static const char *const LOG_CATEGORY_NAMES[] = {"logStatusWarning", "logAll", "logStatusError"};

int fmu_set_debug_logging(FmuHost *host, int logging_on, size_t n, const char *const categories[], int only_these,
                          const char *function)
{
    unsigned chosen = n == 0 ? (unsigned)FMU_LOG_EVERY : 0u;
    for (size_t i = 0; i < n; i++) {
        const char *name = categories == NULL ? NULL : categories[i];
        unsigned bit = 0;
        for (unsigned k = 0; name != NULL && k < sizeof LOG_CATEGORY_NAMES / sizeof *LOG_CATEGORY_NAMES; k++)
            if (strcmp(name, LOG_CATEGORY_NAMES[k]) == 0)
                bit = 1u << k;
        if (bit == 0) {
            fmu_log(host, FMU_ERROR, "%s: categories[%zu]=%s%s%s is invalid: allowed logStatusError, logStatusWarning "
                    "or logAll (the model description's LogCategories)", function, i, name ? "\"" : "",
                    name ? name : "NULL", name ? "\"" : "");
            return 0;
        }
        chosen |= bit;
    }
    if (!logging_on)
        host->log_categories &= ~chosen;
    else
        host->log_categories = only_these ? chosen : host->log_categories | chosen;
    host->warnings_silenced = !(host->log_categories & FMU_LOG_WARNINGS);
    return 1;
}

static void log_message(const FmuHost *host, int status, const char *format, va_list args)
{
    char text[1024];
    vsnprintf(text, sizeof text, format, args);
    const char *category = status >= FMU_ERROR ? "logStatusError" : status == FMU_WARNING ? "logStatusWarning"
                                                                                           : "logAll";
    host->log(host->environment, host->name, status, category, text);
}

void fmu_log(const FmuHost *host, int status, const char *format, ...)
{
    unsigned category_bit = status == FMU_WARNING ? (unsigned)FMU_LOG_WARNINGS : (unsigned)FMU_LOG_OTHERS;
    if (status < FMU_ERROR && !(host->log_categories & category_bit))
        return;
    va_list args;
    va_start(args, format);
    log_message(host, status, format, args);
    va_end(args);
}

void fmu_log_returned_warning(const FmuHost *host, const char *format, ...)
{
    if (host->warnings_silenced)
        return;
    va_list args;
    va_start(args, format);
    log_message(host, FMU_WARNING, format, args);
    va_end(args);
}

const char *fmu_shortest(double x, char *out, size_t size)
{
    for (int precision = 1; precision <= 17; precision++) {
        snprintf(out, size, "%.*g", precision, x);
        if (strtod(out, NULL) == x)
            break;
    }
    if (isfinite(x) && strpbrk(out, ".e") == NULL && strlen(out) + 3 <= size)
        strcat(out, ".0");
    return out;
}

const char *fmu_state_problem(const char *format, const char *kinds, const double *values, char *out, size_t size)
{
    char text[3][40] = {"", "", ""};
    for (int i = 0; i < 3 && kinds[i] != '\0'; i++) {
        if (kinds[i] == 'g')
            fmu_shortest(values[i], text[i], sizeof text[i]);
        else
            snprintf(text[i], sizeof text[i], kinds[i] == 'x' ? "%08llx" : "%lld", (long long)values[i]);
    }
    snprintf(out, size, format, text[0], text[1], text[2]);
    return out;
}

int fmu_parameters_valid(const FmuHost *host, const ParameterInfo *table, int n, const double *values,
                         const char *when)
{
    for (int i = 0; i < n; i++) {
        const ParameterInfo *p = &table[i];
        double x = values[i];
        int ok;
        if (p->n_choices > 0) {
            ok = x == floor(x) && x >= 0.0 && x < p->n_choices;
        } else {
            ok = isfinite(x);
            if (ok && p->has_low)
                ok = p->low_open ? x > p->low : x >= p->low;
            if (ok && p->has_high)
                ok = p->high_open ? x < p->high : x <= p->high;
            if (ok && p->above >= 0)
                ok = x > values[p->above];
            for (int k = 0; ok && k < 2; k++)
                if (p->when[k] >= 0 && values[p->when[k]] == p->when_value[k])
                    ok = x == p->equal;
        }
        if (ok)
            continue;
        char text[32], other[32];
        if (p->n_choices > 0 && x == floor(x))   /* an enumeration's value as an integer */
            snprintf(text, sizeof text, "%.0f", x);
        else
            fmu_shortest(x, text, sizeof text);
        /* a rule with bounds says "> 0"; for a non-finite value say that it must be finite, too */
        const char *finite =
            p->n_choices == 0 && !isfinite(x) && (p->has_low || p->has_high || p->above >= 0) ? "a finite value " : "";
        if (p->above >= 0)
            fmu_log(host, FMU_ERROR, "%s: parameter %s=%s is invalid: allowed %s%s (%s = %s)", when, p->name, text,
                    finite, p->allowed, table[p->above].name, fmu_shortest(values[p->above], other, sizeof other));
        else
            fmu_log(host, FMU_ERROR, "%s: parameter %s=%s is invalid: allowed %s%s", when, p->name, text, finite,
                    p->allowed);
        return 0;
    }
    return 1;
}
