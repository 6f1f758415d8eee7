"""How the package's code gets compiled, private: numba's cache of the kernels (:mod:`.cache`), the second
processes that compile ahead of the one that needs it (:mod:`.prefetch`) and what a command says while it
compiles (:mod:`.notice`).  The kernel decorator is :mod:`wearjoint.core.jit`; the FMU's ahead-of-time
build is in :mod:`wearjoint.fmu.aot` and :mod:`wearjoint.fmu.kernel_ir`."""
