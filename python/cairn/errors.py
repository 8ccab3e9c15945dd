"""Exceptions: what the C library's diagnostics say, with the same words and places as the CLI's
messages (a JSON path such as "parts[2].polygon", or "line:column" in the JSON text)."""


class CairnError(Exception):
    """A cairn call failed. `where` is the JSON path or line:column (may be empty), `message`
    what is wrong and what to do, `file` the file it is in (may be None)."""

    code = 0

    def __init__(self, message, where="", file=None):
        self.message = message
        self.where = where
        self.file = file
        place = ": ".join(p for p in (file, where) if p)
        super().__init__(f"{place}: {message}" if place else message)


class InputError(CairnError, ValueError):
    """Bad input: the file, its JSON, its geometry, or an option (the CLI's exit status 2)."""

    code = 2


class NumericalError(CairnError, ArithmeticError):
    """A solver failed or a result did not verify: no verdict (the CLI's exit status 3)."""

    code = 3


class OutOfMemoryError(CairnError, MemoryError):
    code = 4


class FileError(CairnError, OSError):
    """A file could not be read."""

    code = 5


_BY_CODE = {2: InputError, 3: NumericalError, 4: OutOfMemoryError, 5: FileError}


def error_from_diag(status, where, message, file):
    return _BY_CODE.get(status, CairnError)(message, where, file)
