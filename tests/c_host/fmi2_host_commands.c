/*
 * fmi2_host_commands.c -- the FMI 2.0 host's own commands (documented at the top of fmi2_host.c):
 * setup, the typed get_* and set_*, call_null (each function with NULL arguments) and version.
 */
#define _GNU_SOURCE
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_host.h"

#define REQUIRE(field, name)                                                 \
    do {                                                                     \
        if (api.field == NULL)                                               \
            host_die2("the FMU binary does not export %s", name);            \
    } while (0)

/* ------------------------------------------------------------------------- */
/* FMI 2.0 commands                                                          */

static void cmd_get(size_t ntok)
{
    size_t n = ntok - 1;
    fmi2ValueReference *vr;
    fmi2Status s;
    const char *cmd = H.tok[0];
    fmi2Component comp = H.instance;
    host_need_instance();
    if (n == 0)
        host_die2("usage: %s <vr> [<vr> ...]", cmd);
    vr = host_scratch(n * sizeof *vr);
    for (size_t i = 0; i < n; i++)
        vr[i] = host_parse_vr(H.tok[i + 1]);
    if (strcmp(cmd, "get_real") == 0) {
        fmi2Real *v = host_scratch(n * sizeof *v);
        REQUIRE(getReal, "fmi2GetReal");
        s = host_check(api.getReal(comp, vr, n, v), "fmi2GetReal");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("real %u %.17g\n", vr[i], v[i]);
    } else if (strcmp(cmd, "get_integer") == 0) {
        fmi2Integer *v = host_scratch(n * sizeof *v);
        REQUIRE(getInteger, "fmi2GetInteger");
        s = host_check(api.getInteger(comp, vr, n, v), "fmi2GetInteger");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("integer %u %d\n", vr[i], v[i]);
    } else if (strcmp(cmd, "get_boolean") == 0) {
        fmi2Boolean *v = host_scratch(n * sizeof *v);
        REQUIRE(getBoolean, "fmi2GetBoolean");
        s = host_check(api.getBoolean(comp, vr, n, v), "fmi2GetBoolean");
        printf("%s %s\n", cmd, host_status_name(s));
        if (s <= fmi2Warning)
            for (size_t i = 0; i < n; i++)
                printf("boolean %u %d\n", vr[i], v[i] ? 1 : 0);
    } else {
        fmi2String *v = host_scratch(n * sizeof *v);
        REQUIRE(getString, "fmi2GetString");
        s = host_check(api.getString(comp, vr, n, v), "fmi2GetString");
        printf("%s %s\n", cmd, host_status_name(s));
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
    const char *cmd = H.tok[0];
    fmi2Component comp = H.instance;
    host_need_instance();
    if (n == 0)
        host_die2("usage: %s <vr>=<value> [<vr>=<value> ...]", cmd);
    vr = host_scratch(n * sizeof *vr);
    if (strcmp(cmd, "set_real") == 0) {
        fmi2Real *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = host_parse_double(host_split_assignment(H.tok[i + 1], &vr[i]), "set_real value");
        REQUIRE(setReal, "fmi2SetReal");
        s = host_check(api.setReal(comp, vr, n, v), "fmi2SetReal");
    } else if (strcmp(cmd, "set_integer") == 0) {
        fmi2Integer *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = (fmi2Integer)host_parse_long(host_split_assignment(H.tok[i + 1], &vr[i]), INT_MIN, INT_MAX,
                                                "set_integer value");
        REQUIRE(setInteger, "fmi2SetInteger");
        s = host_check(api.setInteger(comp, vr, n, v), "fmi2SetInteger");
    } else if (strcmp(cmd, "set_boolean") == 0) {
        fmi2Boolean *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = host_parse_bool(host_split_assignment(H.tok[i + 1], &vr[i]));
        REQUIRE(setBoolean, "fmi2SetBoolean");
        s = host_check(api.setBoolean(comp, vr, n, v), "fmi2SetBoolean");
    } else {
        fmi2String *v = host_scratch(n * sizeof *v);
        for (size_t i = 0; i < n; i++)
            v[i] = host_split_assignment(H.tok[i + 1], &vr[i]);
        REQUIRE(setString, "fmi2SetString");
        s = host_check(api.setString(comp, vr, n, v), "fmi2SetString");
    }
    printf("%s %s\n", cmd, host_status_name(s));
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
    fmi2Component c = is_comp ? NULL : H.instance;
    const fmi2ValueReference *vrp = is_vr ? NULL : &vr0;

    if (strcmp(fn, "fmi2Instantiate") == 0) {
        fmi2Component x = NULL;
        const char *name = "call_null", *guid = H.token;
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
            host_die2("call_null fmi2Instantiate: <what> is one of name guid callbacks logger alloc");
        x = api.instantiate(name, fmi2CoSimulation, guid, H.resource, cb, fmi2False, fmi2True);
        printf("call_null %s %s %s\n", fn, what, x == NULL ? "null" : "nonnull");
        H.last_status = x == NULL ? fmi2OK : fmi2Error;
        if (x != NULL && api.freeInstance != NULL)
            api.freeInstance(x);
        return;
    }
    if (!is_comp && !is_values && !is_vr && !is_state)
        host_die2("call_null: <what> is one of component values vr state (or, for fmi2Instantiate, "
                  "name guid callbacks logger alloc), got '%s'", what);
    if (!is_comp)
        host_need_instance();

#define CALL(field, expr)                                                    \
    do {                                                                     \
        REQUIRE(field, fn);                                                  \
        st = (expr);                                                         \
    } while (0)
#define ONLY(cond)                                                           \
    do {                                                                     \
        if (!(cond))                                                         \
            host_die2("call_null: '%s' does not apply to %s", what, fn);     \
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
        CALL(setFMUstate, api.setFMUstate(c, is_comp ? H.slots[0] : NULL));
    } else if (strcmp(fn, "fmi2FreeFMUstate") == 0) {
        ONLY(is_comp || is_values);
        CALL(freeFMUstate, api.freeFMUstate(c, is_values ? NULL : &state));
    } else if (strcmp(fn, "fmi2SerializedFMUstateSize") == 0) {
        ONLY(is_comp || is_values || is_state);
        CALL(serializedFMUstateSize,
             api.serializedFMUstateSize(c, is_state ? NULL : H.slots[0], is_values ? NULL : &size));
    } else if (strcmp(fn, "fmi2SerializeFMUstate") == 0) {
        ONLY(is_comp || is_values || is_state);
        CALL(serializeFMUstate, api.serializeFMUstate(c, is_state ? NULL : H.slots[0],
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
        host_die2("call_null: unsupported function '%s'", fn);
    /* a state the FMU returned despite the NULL argument must not leak */
    if (state != NULL && H.instance != NULL && api.freeFMUstate != NULL && !H.fatal_seen)
        api.freeFMUstate(H.instance, &state);
    H.last_status = st;
    if (st == fmi2Fatal)
        H.fatal_seen = 1;
    printf("call_null %s %s %s\n", fn, what, host_status_name(st));
}

/* the FMI 2.0 commands; 0 if `cmd` is none of them */
int fmi2_host_execute(size_t ntok)
{
    const char *cmd = H.tok[0];
    fmi2Status s;

    if (strcmp(cmd, "setup") == 0) {
        double t0, stop = 0.0, tol = 0.0;
        host_need_args(ntok, 1, 3, "setup <t0> [<stop> [<tol>]]");
        host_need_instance();
        t0 = host_parse_double(H.tok[1], "setup t0");
        if (ntok > 2)
            stop = host_parse_double(H.tok[2], "setup stop");
        if (ntok > 3)
            tol = host_parse_double(H.tok[3], "setup tol");
        REQUIRE(setupExperiment, "fmi2SetupExperiment");
        s = host_check(api.setupExperiment(H.instance, ntok > 3, tol, t0, ntok > 2, stop), "fmi2SetupExperiment");
        printf("setup %s\n", host_status_name(s));
    } else if (strcmp(cmd, "set_real") == 0 || strcmp(cmd, "set_integer") == 0 ||
               strcmp(cmd, "set_boolean") == 0 || strcmp(cmd, "set_string") == 0) {
        cmd_set(ntok);
    } else if (strcmp(cmd, "get_real") == 0 || strcmp(cmd, "get_integer") == 0 ||
               strcmp(cmd, "get_boolean") == 0 || strcmp(cmd, "get_string") == 0) {
        cmd_get(ntok);
    } else if (strcmp(cmd, "call_null") == 0) {
        host_need_args(ntok, 1, 2, "call_null <fmi2Function> [<what>]");
        cmd_call_null(H.tok[1], ntok > 2 ? H.tok[2] : "component");
    } else if (strcmp(cmd, "version") == 0) {
        const char *v, *p;
        host_need_args(ntok, 0, 0, "version");
        REQUIRE(getVersion, "fmi2GetVersion");
        REQUIRE(getTypesPlatform, "fmi2GetTypesPlatform");
        v = api.getVersion();
        p = api.getTypesPlatform();
        printf("version %s %s\n", v ? v : "(null)", p ? p : "(null)");
    } else {
        return 0;
    }
    return 1;
}
