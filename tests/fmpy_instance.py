"""Starting an fmpy FMI 2.0 instance (FMU2Slave or FMU2Model) of the joint FMU with a joint's parameters."""
from wearjoint.fmu import variables as fv


def enter_initialisation(fmu, vr, params=None):
    """setupExperiment(0) and enterInitializationMode on the instantiated ``fmu``, then, if ``params``
    (JointParameters) is given, every FMU parameter reproducing it (Reals and Integers); ``vr``: the
    value references by name.  The caller exits Initialization Mode."""
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    if params is not None:
        reals, integers = fv.fmi_parameter_values_by_type(params)
        fmu.setReal([vr[k] for k in reals], list(reals.values()))
        fmu.setInteger([vr[k] for k in integers], list(integers.values()))
