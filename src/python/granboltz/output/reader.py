"""Reader: reads one open granboltz output, checking each dataset and attribute against the
layout's Spec (granboltz.output.layout); every failure is RunReadError naming the file and the object.
"""

import h5py
import numpy as np

from .io import RunReadError, check_finite, reading, text


class Reader:
    """Reads one open output, checking each dataset and attribute against its Spec; every
    failure is RunReadError naming the file and the object."""

    def __init__(self, f, path, model):
        self.f, self.path, self.model = f, path, model
        self._attrs = {}  # {owner: its attributes}, each group's read once (a steady group has many)

    def why(self, condition=""):
        return f"every {self.model} output{' with ' + condition if condition else ''} has it"

    def fail(self, name, problem):
        raise RunReadError(self.path, name, problem)

    def dataset(self, spec, read=True):
        label = f"dataset /{spec.name}"
        with reading(self.path, label):
            obj = self.f.get(spec.name)
            if obj is None:
                self.fail(label, f"missing ({spec.why})" if spec.why else "missing")
            if not isinstance(obj, h5py.Dataset):
                self.fail(label, "is a group, not a dataset")
            dtype = obj.dtype
            if dtype.kind != spec.dtype.kind or dtype.itemsize != spec.dtype.itemsize:
                self.fail(label, f"has dtype {dtype}, not {spec.dtype}")
            if spec.shape is not None and obj.shape != tuple(spec.shape):
                self.fail(label, f"has shape {obj.shape}, not {tuple(spec.shape)}")
            if not read:
                return None
            data = obj[()]
        if spec.finite:
            check_finite(data, self.path, label)
        return data

    def group(self, name, why):
        label = f"group /{name}"
        with reading(self.path, label):
            obj = self.f.get(name)
            if obj is None:
                self.fail(label, f"missing ({why})")
            if not isinstance(obj, h5py.Group):
                self.fail(label, "is a dataset, not a group")
            return obj

    def attributes(self, owner, why):
        """{key: value} of every attribute of the group `owner` ("/": the root)."""
        if owner not in self._attrs:
            with reading(self.path, "the root attributes" if owner == "/" else f"the attributes of /{owner}"):
                obj = self.f if owner == "/" else self.group(owner, why)
                self._attrs[owner] = dict(obj.attrs)
        return self._attrs[owner]

    def attribute(self, owner, key, why):
        where = "" if owner == "/" else f"/{owner}"
        attrs = self.attributes(owner, why)
        if key not in attrs:
            name = f"attribute {key}" + (f" of {where}" if where else "")
            self.fail(name, f"missing ({why})" if why else "missing")
        return attrs[key]

    def integer(self, owner, key, why, minimum=0):
        value = self.attribute(owner, key, why)
        name = f"attribute {key}" + ("" if owner == "/" else f" of /{owner}")
        if not (isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))):
            self.fail(name, f"is not an integer ({value!r})")
        if value < minimum:
            self.fail(name, f"is {value}, less than {minimum}")
        return int(value)

    def number(self, owner, key, why, nan=False):
        """A finite number (nan=True: NaN too, for what the simulator cannot estimate)."""
        value = self.attribute(owner, key, why)
        name = f"attribute {key}" + ("" if owner == "/" else f" of /{owner}")
        if not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, (bool, np.bool_)) \
                or not (np.isfinite(value) or (nan and np.isnan(value))):
            self.fail(name, f"is not a finite number ({value!r})")
        return float(value)

    def text(self, owner, key, why):
        value = self.attribute(owner, key, why)
        name = f"attribute {key}" + ("" if owner == "/" else f" of /{owner}")
        if not isinstance(value, (bytes, str)):
            self.fail(name, f"is not text ({value!r})")
        with reading(self.path, name):
            return text(value)

    def exists(self, name):
        """Whether the file has an object at the path `name` (group or dataset)."""
        with reading(self.path, f"object /{name}"):
            return name in self.f

    def has_attribute(self, owner, key):
        with reading(self.path, f"group /{owner}"):
            if not isinstance(self.f.get(owner), h5py.Group):
                return False
        return key in self.attributes(owner, "")

    def names(self, group):
        """The member names of a group the layout has already checked ("/": the root's)."""
        with reading(self.path, "the root group" if group == "/" else f"group /{group}"):
            return list(self.f[group])
