"""How the pure-Python part of the package reports what it cannot do: needlesim.InputError
(or a subclass that is also the matching builtin) naming the file or argument, what is
wrong and what is allowed, worded as the CLI words input errors (docs/python.md "Errors")."""
import contextlib

from needlesim._core import ArgumentTypeError, InputError, NotFoundError, SolverError, UnknownNameError

__all__ = ["ArgumentTypeError", "InputError", "NotFoundError", "UnknownNameError", "input_error", "printable",
           "reading", "require_type"]


def printable(text, limit=200):
    """`text` as it may be shown on a terminal: control characters escaped, cut after `limit` characters."""
    text = str(text)
    out = "".join(c if c.isprintable() else repr(c)[1:-1] for c in text[:limit])
    return out + ("... (%d characters)" % len(text) if len(text) > limit else "")


def input_error(where, problem, allowed=None, cls=InputError):
    """The error "<where>: <problem>; allowed: <allowed>" of class `cls` (InputError or a subclass)."""
    message = "%s: %s" % (printable(where), problem)
    if allowed:
        message += "; allowed: " + allowed
    return cls(message)


def require_type(call, what, value, types, allowed):
    """ArgumentTypeError unless `value` is an instance of `types`."""
    if not isinstance(value, types):
        raise ArgumentTypeError("%s: %s must be %s, not %s" % (call, what, allowed, type(value).__name__))


@contextlib.contextmanager
def reading(path, allowed):
    """Turns what reading `path` raises into an InputError naming the file (NotFoundError where
    it does not exist); an InputError raised inside passes unchanged."""
    try:
        yield
    except (InputError, SolverError):
        raise
    except FileNotFoundError:
        raise input_error(path, "does not exist", allowed, NotFoundError) from None
    except IsADirectoryError:
        raise input_error(path, "is a folder, not a file", allowed) from None
    except UnicodeDecodeError as e:
        raise input_error(path, "is not UTF-8 text (byte %d)" % e.start, allowed) from None
    except MemoryError:
        raise input_error(path, "is too large to read into memory", allowed) from None
    except Exception as e:  # OSError, ValueError, ... and what h5py raises for a damaged file (RuntimeError)
        raise input_error(path, "cannot be read: %s" % printable(e), allowed) from None
