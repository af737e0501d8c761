"""The command line (``supcoord``); see :mod:`supcoord.cli.main`."""
