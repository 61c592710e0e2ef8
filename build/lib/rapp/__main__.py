"""``python -m rapp``: see :mod:`rapp.cli`.

Python imports the package before this module, and ``rapp/__init__.py`` installs
:func:`rapp.interrupts.guard_startup` before its own imports, so a Ctrl-C at any moment of
start-up ends the run with one line and exit code 130; :func:`rapp.cli.command` keeps it so
through the end of the run.
"""

if __name__ == "__main__":
    from rapp import interrupts

    interrupts.guard_startup()  # holds even if the package was imported some other way first
    from rapp.cli import command

    command()
