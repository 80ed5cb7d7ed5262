"""``python -m acoustiviz`` runs the command-line tool."""

import sys

if __name__ == "__main__":
    try:
        from .cli import main
    except KeyboardInterrupt:  # a Ctrl-C while the command line itself is imported: the same line and status
        import signal

        signal.signal(signal.SIGINT, signal.SIG_IGN)
        from .cli import command_of, interrupted

        sys.exit(interrupted(command_of(sys.argv[1:]), standalone=True))
    sys.exit(main())
