"""The arguments of granboltz.simulate and granboltz.Simulation checked and normalised: a config
dict made plain YAML (NumPy values as numbers, within the reader's bounds) or a config file read
without blocking, paths as (text, bytes), integer arguments typed and ranged. Every refusal is one
line: ConfigError, TypeError, ValueError or FileNotFoundError."""

import numbers
import os
import stat

import numpy as np
import yaml

from .. import _core

ConfigError = _core.ConfigError

MAX_THREADS = 1024  # the config's bound on `threads` (app/config.cpp)


def shorten(value, limit=80):
    """repr(value) for a one-line message, cut to about `limit` characters."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[:limit]}… ({len(text)} characters)"


def _plain(value, key, origin, depth=1, size=None):
    """The config dict as YAML can dump it: NumPy scalars and arrays (np.float64, np.int64,
    np.bool_, a 0-d array, np.linspace's 1-d array) as the numbers and lists they hold, tuples as
    lists, anywhere in it. Within the simulator's config reader's bounds (_core.kMaxConfigDepth
    nested mappings and lists, _core.kMaxConfigNodes values, _core.kMaxConfigBytes of text),
    checked before YAML is written (200,000 numbers take yaml.safe_dump half a minute); anything
    that is no config value is a ConfigError naming its key."""
    if size is None:
        size = [0, 0]  # values, bytes of YAML (about)
    size[0] += 1
    if size[0] > _core.kMaxConfigNodes:
        raise ConfigError(f"{origin}: more than {_core.kMaxConfigNodes} values (at {shorten(key, 120)}); "
                          f"a config has at most {_core.kMaxConfigNodes}")
    if isinstance(value, np.ndarray):
        if value.size > _core.kMaxConfigNodes:
            raise ConfigError(f"{origin}: {key}: an array of {value.size} values; a config has at most "
                              f"{_core.kMaxConfigNodes}")
        if value.dtype.kind not in "biuf":
            raise ConfigError(f"{origin}: {key} = {shorten(value)}: an array of dtype {value.dtype} is "
                              "not a config value (an array of numbers or booleans is)")
        value = value.tolist()  # 0-d: a Python scalar; else nested lists of them
    if isinstance(value, (dict, list, tuple)):
        if depth > _core.kMaxConfigDepth:
            raise ConfigError(f"{origin}: nested more than {_core.kMaxConfigDepth} levels deep "
                              f"(at {shorten(key, 120)})")
        if isinstance(value, dict):
            out = {}
            for k, v in value.items():
                name = _plain(k, f"a key of {key}", origin, depth + 1, size)
                if isinstance(name, (dict, list)):
                    raise ConfigError(f"{origin}: {key}: the key {shorten(k)} is not a scalar")
                out[name] = _plain(v, f"{key}.{name}" if key != "the config" else str(name),
                                   origin, depth + 1, size)
            return out
        return [_plain(v, f"{key}[{i}]", origin, depth + 1, size) for i, v in enumerate(value)]
    size[1] += len(value) if isinstance(value, str) else 8  # about what YAML will write
    if size[1] > _core.kMaxConfigBytes:
        raise ConfigError(f"{origin}: more than {_core.kMaxConfigBytes} bytes of YAML (at "
                          f"{shorten(key, 120)}); a config is at most {_core.kMaxConfigBytes} bytes")
    if isinstance(value, str):
        try:
            value.encode("utf-8")
        except UnicodeEncodeError:  # a lone surrogate (os.fsdecode of bytes that are not UTF-8)
            raise ConfigError(f"{origin}: {key} = {shorten(value)}: not valid Unicode text") from None
    if value is None or type(value) in (bool, int, float, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return str(value)
    raise ConfigError(f"{origin}: {key} = {shorten(value)}: a {type(value).__name__} is not a config "
                      "value (numbers, strings, booleans, lists and mappings are)")


def path_argument(value, what):
    """(str, bytes) of a path argument (str, bytes or os.PathLike): the str for messages and
    Python, the bytes for the simulator, so that a path that is not UTF-8 is the same file."""
    if not isinstance(value, (str, bytes, os.PathLike)):
        raise TypeError(f"{what} must be a path (str, bytes or os.PathLike), not {type(value).__name__}")
    path = os.fspath(value)
    text, raw = os.fsdecode(path), os.fsencode(path)
    if not raw:
        raise ValueError(f"{what}: the path is empty")
    if b"\0" in raw:
        raise ValueError(f"{what} {text!r}: contains a NUL character")
    return text, raw


def config_text(config):
    """(YAML text as bytes, origin for messages, the config file's path or b"") of a config dict
    or a path to a YAML file."""
    if isinstance(config, dict):
        plain = _plain(config, "the config", "<config dict>")
        try:  # libyaml's emitter where PyYAML has it: the same YAML, far faster
            text = yaml.dump(plain, Dumper=getattr(yaml, "CSafeDumper", yaml.SafeDumper), sort_keys=False)
        except yaml.YAMLError as e:  # not expected: _plain leaves only YAML's own types
            raise ConfigError(f"<config dict>: cannot be written as YAML ({str(e).splitlines()[0]})") from None
        return text.encode("utf-8", "surrogateescape"), b"<config dict>", b""
    if isinstance(config, (str, bytes, os.PathLike)):
        shown, raw = path_argument(config, "config file")
        # Opened without blocking (a FIFO has no writer) and checked by what was opened: a
        # directory, a FIFO or a device is refused as the CLI refuses it.
        try:
            fd = os.open(raw, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
        except FileNotFoundError:
            raise FileNotFoundError(f"config file {shown!r}: no such file") from None
        except OSError as e:  # permissions, a file where a folder should be, a loop of links
            raise ConfigError(f"{shown}: cannot open config file ({e.strerror})") from None
        try:
            mode = os.fstat(fd).st_mode
            if stat.S_ISDIR(mode):
                raise ConfigError(f"{shown}: is a directory, not a config file")
            if not stat.S_ISREG(mode):
                raise ConfigError(f"{shown}: is not a regular file (a FIFO or a device?), not a config file")
            with os.fdopen(os.dup(fd), "rb") as f:
                text = f.read(_core.kMaxConfigBytes + 1)  # the simulator refuses a longer one
        finally:
            os.close(fd)
        return text, raw, raw
    raise TypeError(f"config must be a dict or a path to a YAML file, not {type(config).__name__}")


def integer_argument(name, value, lo, hi, allowed):
    """An integer argument (int or a NumPy integer; not a bool, not a float) in lo..hi."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} = {shorten(value)}: must be an integer, {allowed} "
                        f"(not a {type(value).__name__})")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {shorten(value)}: must be an integer, {allowed}")
    return value


def real_array(call, what, value, shape):
    """value as a C-contiguous float64 array of `shape` (None: any length, the particle count
    the engine checks), finite and at most 1e150 in magnitude:
    TypeError for what is not an array of real numbers, ValueError (one line) for a wrong shape
    or a bad entry."""
    if isinstance(value, (str, bytes, dict)) or value is None:
        raise TypeError(f"{call}: {what} must be an array of real numbers, not a {type(value).__name__}")
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError) as e:  # a ragged nesting
        raise ValueError(f"{call}: {what} is not a rectangular array ({str(e).splitlines()[0][:80]})") from None
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"{call}: {what} must be real numbers, not dtype {arr.dtype}")
    if arr.ndim != len(shape) or any(k is not None and k != m for k, m in zip(shape, arr.shape)):
        want = "(" + ", ".join("n" if k is None else str(k) for k in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError(f"{call}: {what} has shape {arr.shape}, not {want}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    bad = ~(np.abs(arr) <= 1e150)
    if bad.any():
        index = tuple(int(k) for k in np.argwhere(bad)[0])
        shown = index[0] if len(index) == 1 else ", ".join(str(k) for k in index)
        raise ValueError(f"{call}: {what}[{shown}] = {float(arr[index])!r}: must be finite and at most "
                         "1e150 in magnitude")
    return arr
