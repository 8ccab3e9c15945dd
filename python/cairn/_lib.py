"""The C library, through ctypes: libcairn.so.0 found, its few entry points declared, and the
diagnostics it fills turned into exceptions."""
import ctypes
import ctypes.util
import os

from .errors import error_from_diag


class Diag(ctypes.Structure):
    """cnDiag (include/cairn/status.h)."""

    _fields_ = [
        ("code", ctypes.c_int),
        ("where", ctypes.c_char * 256),
        ("message", ctypes.c_char * 1024),
        ("file", ctypes.c_char * 256),
    ]


class LoadOptions(ctypes.Structure):
    """cnLoadOptions (include/cairn/model.h)."""

    _fields_ = [
        ("friction", ctypes.c_double),
        ("density", ctypes.c_double),
        ("tolerance", ctypes.c_double),
        ("supports", ctypes.c_char_p),
    ]


# the ranges the CLI's --friction, --density and --tolerance accept, with its words
_RANGES = {
    "friction": (0.0, 1e6, True, "a number from 0 (frictionless) to 1e6, e.g. 0.6"),
    "density": (0.0, 1e100, False, "a positive number up to 1e100"),
    "tolerance": (1e-12, 0.1, True, "a relative tolerance from 1e-12 to 0.1, e.g. 1e-4"),
}


def _option(name, value):
    """An override as the library takes it: NaN for "not given" (so a NaN given is refused)."""
    if value is None:
        return float("nan")
    v = float(value)
    lo, hi, lo_ok, words = _RANGES[name]
    if not (v == v and (v >= lo if lo_ok else v > lo) and v <= hi):
        raise ValueError(f"{name} must be {words}, got {value!r}")
    return v


def load_options(friction=None, density=None, tolerance=None, supports=None):
    return LoadOptions(_option("friction", friction), _option("density", density), _option("tolerance", tolerance),
                       None if supports is None else ",".join(str(k) for k in supports).encode())


def _candidates():
    env = os.environ.get("CAIRN_LIBRARY")
    if env:
        yield env
        return
    found = ctypes.util.find_library("cairn")
    if found:
        yield found
    yield "libcairn.so.0"
    yield from _in_prefixes("libcairn.so.0")


def _in_prefixes(name):
    """name under the usual install prefixes' library directories (make install's default
    prefix is /usr/local, whose lib/ the loader may not search)."""
    for prefix in ("/usr/local", "/usr"):
        for sub in ("lib", "lib64", "lib/x86_64-linux-gnu", "lib/aarch64-linux-gnu"):
            yield os.path.join(prefix, sub, name)


def _load():
    tried = []
    for name in _candidates():
        try:
            return ctypes.CDLL(name)
        except OSError as e:
            tried.append(name)
    raise ImportError(
        "cairn: the C library libcairn.so.0 was not found; install it (make install "
        "PREFIX=...) or set CAIRN_LIBRARY to its path (tried: " + ", ".join(tried) + ")"
    )


lib = _load()

_P = ctypes.c_void_p
lib.cn_version.restype = ctypes.c_char_p
lib.cn_version.argtypes = []
lib.cn_assembly_load_string.restype = ctypes.c_int
lib.cn_assembly_load_string.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(_P), ctypes.POINTER(Diag)]
lib.cn_assembly_load_file.restype = ctypes.c_int
lib.cn_assembly_load_file.argtypes = [ctypes.c_char_p, ctypes.POINTER(_P), ctypes.POINTER(Diag)]
lib.cn_assembly_load_with.restype = ctypes.c_int
lib.cn_assembly_load_with.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(LoadOptions),
                                      ctypes.POINTER(_P), ctypes.POINTER(Diag)]
lib.cn_assembly_load_string_with.restype = ctypes.c_int
lib.cn_assembly_load_string_with.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(LoadOptions),
                                             ctypes.POINTER(_P), ctypes.POINTER(Diag)]
lib.cn_assembly_free.restype = None
lib.cn_assembly_free.argtypes = [_P]
lib.cn_run_json.restype = ctypes.c_int
lib.cn_run_json.argtypes = [_P, ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(_P), ctypes.POINTER(ctypes.c_int), ctypes.POINTER(Diag)]
lib.cn_string_free.restype = None
lib.cn_string_free.argtypes = [_P]


_figure_lib = None


def _figure_candidates():
    env = os.environ.get("CAIRN_FIGURE_LIBRARY")
    if env:
        yield env
        return
    # beside the libcairn that was loaded, then wherever the loader finds it
    path = getattr(lib, "_name", "")
    if os.sep in path:
        yield os.path.join(os.path.dirname(path), "libcairn_figure.so.0")
    found = ctypes.util.find_library("cairn_figure")
    if found:
        yield found
    yield "libcairn_figure.so.0"
    yield from _in_prefixes("libcairn_figure.so.0")


def figure_lib():
    """libcairn_figure (cairo), loaded the first time a figure is asked for."""
    global _figure_lib
    if _figure_lib is None:
        tried = []
        for name in _figure_candidates():
            try:
                f = ctypes.CDLL(name)
                break
            except OSError:
                tried.append(name)
        else:
            raise ImportError(
                "cairn: figures need libcairn_figure.so.0 (installed with libcairn by make install), which "
                "was not found; set CAIRN_FIGURE_LIBRARY to its path (tried: " + ", ".join(tried) + ")")
        try:
            f.cn_figure_run_json.restype = ctypes.c_int
        except AttributeError:
            raise ImportError("cairn: " + f._name + " is older than this package: it has no cn_figure_run_json; "
                              "install the libcairn_figure of the same version") from None
        f.cn_figure_run_json.argtypes = lib.cn_run_json.argtypes
        _figure_lib = f
    return _figure_lib


def version():
    return lib.cn_version().decode()


def _check(status, diag, source):
    if status != 0:
        raise error_from_diag(status, diag.where.decode(errors="replace"),
                              diag.message.decode(errors="replace"),
                              diag.file.decode(errors="replace") or source)


def load_text(text, source, opts):
    ptr = _P()
    diag = Diag()
    st = lib.cn_assembly_load_string_with(text.encode(), source.encode() if source else None, ctypes.byref(opts),
                                          ctypes.byref(ptr), ctypes.byref(diag))
    _check(st, diag, source)
    return ptr


def load_file(path, plan, opts):
    ptr = _P()
    diag = Diag()
    st = lib.cn_assembly_load_with(os.fsencode(path), None if plan is None else os.fsencode(plan), None,
                                   ctypes.byref(opts), ctypes.byref(ptr), ctypes.byref(diag))
    _check(st, diag, os.fsdecode(path))
    return ptr


def free(ptr):
    lib.cn_assembly_free(ptr)


def run(ptr, command, options_json, source, figures=False):
    out = _P()
    outcome = ctypes.c_int(-1)
    diag = Diag()
    fn = figure_lib().cn_figure_run_json if figures else lib.cn_run_json
    st = fn(ptr, command.encode(), options_json.encode(), ctypes.byref(out),
                         ctypes.byref(outcome), ctypes.byref(diag))
    _check(st, diag, source)
    try:
        text = ctypes.string_at(out.value).decode()
    finally:
        lib.cn_string_free(out)
    return text, outcome.value
