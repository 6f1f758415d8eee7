"""The FMUs' sources, installed as ``wearjoint.fmu_src``: ``fmi/`` the FMI 2.0/3.0 layer every native model
shares, ``joint/`` and ``slider_crank/`` the models' C parts, ``pythonfmu/`` the pythonfmu slave and its status
shim.  Builders: :mod:`wearjoint.fmu.build_native`, :mod:`wearjoint.fmu.build_pythonfmu`."""
