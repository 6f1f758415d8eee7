"""The studies behind the commands `wear-study`, `calibrate` and `cosim-study` and the numerical studies of
docs/ (damping, masters): engines and their outputs, above the library (not cross-checks: those are
``wearjoint.validation``)."""
