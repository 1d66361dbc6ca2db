"""The compiled core: the state's layout, the step's stages (one module each), the
pipeline that runs them per world and the runner that drives it over a batch. Every
kernel of the engine lives here (``_jit.kernel``); the facades (``World``, the shapes)
read and write the state through ``impulse2d.edit`` and ``impulse2d.structure``."""
