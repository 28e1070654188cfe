"""``python -m swarmex``: the same entry point as the ``swarmex`` console script."""

from swarmex.cli import entry

if __name__ == "__main__":
    entry()
