"""The grid of a study: dotted keys set in a config (through mappings, and through lists by an
item's name or index: dsmc.species.heavy.mass), and the replica axis (`replicas: R` or a list of
seeds) that expands as a last grid key `seed`."""

import copy

from .safe_yaml import StudyError, one_line, show

MAX_REPLICAS = 10_000


def check_replicas(spec, base, grid, path):
    """The seeds of the replica axis: `replicas: R` (base.seed, base.seed + 1, ...) or a list of
    distinct seeds; None without one."""
    if "replicas" not in spec:
        return None
    r = spec["replicas"]
    if "seed" in grid:
        raise StudyError(f"{path}: replicas and grid.seed: give the seeds in one of them")
    if isinstance(r, bool) or not isinstance(r, (int, list)):
        raise StudyError(f"{path}: replicas must be a number of replicas or a list of seeds (got {show(r, 60)})")
    if isinstance(r, int):
        if not 1 <= r <= MAX_REPLICAS:
            raise StudyError(f"{path}: replicas = {r}: must be from 1 to {MAX_REPLICAS}")
        seed = base.get("seed")
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise StudyError(f"{path}: replicas = {r} counts from base.seed, which must be a non-negative integer "
                             f"(got {show(seed, 40)}); or give replicas as a list of seeds")
        seeds = [seed + k for k in range(r)]
    else:
        seeds = r
        if not seeds or len(seeds) > MAX_REPLICAS:
            raise StudyError(f"{path}: replicas: a list of 1 to {MAX_REPLICAS} seeds (got {len(seeds)})")
    for s in seeds:
        if isinstance(s, bool) or not isinstance(s, int) or not 0 <= s < 1 << 64:
            raise StudyError(f"{path}: replicas: seed {show(s, 40)} is not an integer from 0 to 2^64 - 1")
    if len(set(seeds)) != len(seeds):
        raise StudyError(f"{path}: replicas repeats a seed")
    return seeds


def replica_seeds(spec):
    """The seeds of a checked study's replica axis, or None."""
    return check_replicas(spec, spec["base"], spec["grid"], "study")


def full_grid(spec):
    """The grid of a checked study with its replica axis as the last key, `seed`."""
    seeds = replica_seeds(spec)
    return {**spec["grid"], "seed": seeds} if seeds else dict(spec["grid"])


def _item(items, part, key, through, path):
    """The index of a list's item that the grid key's `part` names: the item whose `name` is
    part (a species), else part as an index."""
    named = [i for i, item in enumerate(items) if isinstance(item, dict) and item.get("name") == part]
    if named:
        return named[0]
    if part.isdigit() and int(part) < len(items):
        return int(part)
    names = [str(item["name"]) for item in items if isinstance(item, dict) and "name" in item]
    have = (f"names {', '.join(names)}" if names else "no names") + f", or indices 0 to {len(items) - 1}"
    raise StudyError(f"{path}: grid key {show(key, 60)}: {through} has no item {show(part, 40)} ({one_line(have, 80)})")


def set_key(config, key, value, path="study"):
    """Set the dotted `key` of `config` to `value`, creating mappings on the way. A part of the
    key may address an item of a list by its `name` (dsmc.species.heavy.mass) or its index."""
    node, parts = config, key.split(".")
    for i, part in enumerate(parts[:-1]):
        through = one_line(".".join(parts[:i + 1]), 60)
        if isinstance(node, list):
            child = node[_item(node, part, key, ".".join(parts[:i]), path)]
        else:
            child = node.setdefault(part, {})
        if not isinstance(child, (dict, list)):
            raise StudyError(f"{path}: grid key {show(key, 60)}: {through} is not a mapping in base")
        node = child
    last = parts[-1]
    if isinstance(node, list):
        node[_item(node, last, key, ".".join(parts[:-1]), path)] = copy.deepcopy(value)
    else:
        node[last] = copy.deepcopy(value)
    return config


def _get(config, key):
    node = config
    for part in key.split("."):
        node = node[part]
    return node
