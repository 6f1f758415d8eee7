"""The kernels compile without numba's reference counting (NRT), through numba's private
``_nrt`` option (wearjoint.core.jit): if a numba release drops or renames it, these
tests fail loudly instead of the kernels silently getting twice as slow."""
import os
import subprocess
import sys
import textwrap

from numba.core.registry import CPUDispatcher

from wearjoint.core import contact, integrators, slider_crank, wear

# a kernel touching what NRT reference-counts: array views, held in a tuple
PROBE = textwrap.dedent('''
    import numpy as np
    from numba import njit
    from wearjoint.core.geometry import block_minimum_depth
    from wearjoint.core.jit import kernel

    def views(a, out):
        pair = (a[1:], a[:2])
        s = 0.0
        for k in range(pair[0].shape[0]):
            s += pair[0][k]
        out[0] = s + pair[1][0]

    a, out = np.arange(40.0), np.zeros(2)
    for name, dispatcher in (("kernel", kernel(views)), ("njit", njit(views)), ("block_minimum_depth",
                                                                             block_minimum_depth)):
        dispatcher(a, out)
        ir = "".join(dispatcher.inspect_llvm().values())
        assert len(ir) > 1000, name
        print(name, "NRT_incref" in ir or "NRT_decref" in ir)
''')

HOT_KERNELS = (slider_crank.derivative, slider_crank.accelerations, slider_crank.open_joint_accelerations_rotated,
               integrators.rk4_step, integrators.accept_point, integrators.record_step,
               integrators._integrate_steps, contact.evaluate_contact, contact.evaluate_contact_scalars,
               wear.accept_contact, wear.advance_joint)


def test_the_hot_kernels_are_compiled_without_nrt():
    """Each hot kernel is a :func:`wearjoint.core.jit.kernel` (not a plain njit, which would bring NRT back)."""
    for dispatcher in HOT_KERNELS:
        assert isinstance(dispatcher, CPUDispatcher), dispatcher
        assert dispatcher.targetoptions.get("_nrt") is False, dispatcher.py_func.__qualname__


def test_kernel_llvm_ir_has_no_reference_counting(tmp_path):
    """Compiled in a fresh process with an empty cache (cached code has no LLVM IR to inspect):
    a kernel's IR calls neither NRT_incref nor NRT_decref, while the same function under
    plain njit does (so the probe would notice NRT coming back)."""
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=600,
                          env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")})
    assert done.returncode == 0, done.stderr[-3000:]
    uses_nrt = dict(line.split() for line in done.stdout.splitlines())
    assert uses_nrt == {"kernel": "False", "njit": "True", "block_minimum_depth": "False"}
