"""The FMI status codes the Python side compares against (fmi2Status and fmi3Status share them)."""

FMI_OK, FMI_WARNING, FMI_DISCARD, FMI_ERROR, FMI_FATAL = range(5)

__all__ = ["FMI_DISCARD", "FMI_ERROR", "FMI_FATAL", "FMI_OK", "FMI_WARNING"]
