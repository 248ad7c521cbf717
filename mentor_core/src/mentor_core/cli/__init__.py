"""The command-line tools: ``mentor-train``, ``mentor-eval``, ``mentor-report``, ``mentor-draw``
and ``mentor-xor``.

Each one parses its arguments, calls the library and turns a ``MentorError`` into one line on
stderr and a non-zero exit. The top layer: it may import every wing, and no wing imports it.
"""
