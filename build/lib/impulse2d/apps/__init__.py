"""What is built on the engine for people to watch and play: the demo scenes and their
command (``python -m impulse2d.apps.demo``), the sandbox and the pygame player
(``python -m impulse2d.apps.play``)."""
