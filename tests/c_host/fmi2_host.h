/*
 * fmi2_host.h -- what the two files of the FMI 2.0 host share: the FMI 2.0 functions of its own
 * commands and the callbacks it gives the FMU (fmi2_host.c), its own commands (fmi2_host_commands.c).
 */
#ifndef FMI2_HOST_H
#define FMI2_HOST_H

#include <stddef.h>

#include "fmi2FunctionTypes.h"
#include "host_common.h"

/* The FMI 2.0 functions of the host's own commands (the shared ones: H.fn); loaded by fmi2_host.c */
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
    fmi2DoStepTYPE *doStep;
    fmi2CancelStepTYPE *cancelStep;
    fmi2GetStatusTYPE *getStatus;
    fmi2GetRealStatusTYPE *getRealStatus;
    fmi2GetIntegerStatusTYPE *getIntegerStatus;
    fmi2GetBooleanStatusTYPE *getBooleanStatus;
    fmi2GetStringStatusTYPE *getStringStatus;
} Api;

extern Api api;

/* the callbacks given to the FMU: complete, without a logger, without allocateMemory (call_null) */
extern const fmi2CallbackFunctions callbacks, callbacks_no_logger, callbacks_no_alloc;

/* the FMI 2.0 commands (fmi2_host_commands.c); 0 if `cmd` is none of them */
int fmi2_host_execute(size_t ntok);

#endif
