"""The histograms of a run file, read lazily: run.histograms of granboltz.read_run."""

from collections.abc import Mapping

import h5py

from .io import RunReadError, open_run, read_dataset, reading
from .reader import Reader


class LazyHistograms(Mapping):
    """The histograms of a run file by group name ({dataset name: array} each), read from the
    file on first access and then kept: large histograms cost nothing until they are used."""

    def __init__(self, path, names, layouts=None):
        self._path, self._names, self._cache = str(path), tuple(names), {}
        # {group: [Spec]}: the datasets read_run found in each group, checked again when read
        self._layouts = dict(layouts or {})

    def __getitem__(self, name):
        if name not in self._names:
            raise KeyError(f"{self._path} has no histogram {name!r} (it has: {', '.join(self._names) or 'none'})")
        if name not in self._cache:
            with open_run(self._path) as f:
                reader = Reader(f, self._path, None)
                with reading(self._path, f"group /{name}"):
                    group = f.get(name)
                    if not isinstance(group, h5py.Group):
                        raise RunReadError(self._path, f"group /{name}", "missing (read_run found it)")
                    keys = [key for key in group if isinstance(group.get(key), h5py.Dataset)]
                out = {}
                for spec in self._layouts.get(name, ()):
                    out[spec.name.rpartition("/")[2]] = reader.dataset(spec)
                for key in keys:
                    if key not in out:
                        out[key] = read_dataset(f, f"{name}/{key}", self._path)
                self._cache[name] = out
        return self._cache[name]

    def __iter__(self):
        return iter(self._names)

    def __len__(self):
        return len(self._names)
