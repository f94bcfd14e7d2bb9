"""One module per ``f16mmae`` subcommand; each defines ``register(subparsers)``.

``register`` adds the subcommand's parser (with a ``--help`` that teaches) and sets
``func`` on it: ``func(args) -> int`` is the process exit code.
"""
