"""Ctrl-C as a terminal delivers it, for tests that interrupt a command in a child process."""
import signal


def default_sigint() -> None:
    """In the child before it starts (``preexec_fn``): SIGINT's default action.  A child inherits an ignored SIGINT
    (a pytest-xdist worker, or a suite started in the background by a shell without job control, runs with SIGINT
    ignored), and Python then never raises KeyboardInterrupt: the command runs on and exits 0."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
