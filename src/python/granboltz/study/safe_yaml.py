"""Reading the YAML of parameter studies (granboltz.study) under the limits of a config
(docs/config.md): a regular UTF-8 file of at most MAX_BYTES, opened without blocking (a FIFO is
refused, never read); at most MAX_NODES YAML nodes as written and again with every alias counted
as the nodes it stands for (an alias bomb is refused without being expanded); at most MAX_DEPTH
levels, also through aliases; no alias inside the node it refers to; no key given twice. Every
failure is StudyError with a one-line message."""

import os
import stat

import yaml

MAX_BYTES = 1 << 20        # a study file
MAX_NODES = 100_000        # YAML nodes, as written and again with every alias expanded
MAX_DEPTH = 64             # nested mappings and sequences, also through aliases


class StudyError(ValueError):
    """A study file or folder that cannot be used, a simulator that cannot be found, or runs
    missing or damaged (table()). The message is one line."""


def one_line(text, limit=80):
    """Free text on one line for a message: control and other unprintable characters escaped,
    cut at `limit` characters (saying how long it was)."""
    text = "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in str(text))
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def show(value, limit=80):
    """A value on one line for a message: its repr, cut at `limit`."""
    return one_line(repr(value), limit)


def lstat(path):
    """os.lstat(path), or None when nothing is there; other failures raise StudyError."""
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise StudyError(f"{path}: cannot look at it ({e.strerror or e})") from None


def file_kind(mode):
    """What a non-regular file is ('a symbolic link', 'a directory', ...) from its st_mode."""
    for test, name in ((stat.S_ISLNK, "a symbolic link"), (stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISSOCK, "a socket"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device")):
        if test(mode):
            return name
    return "not a regular file"


class _Limited(yaml.YAMLError):
    """A study file over a limit of _Loader (not a YAML syntax error)."""

    def __init__(self, problem, mark=None):
        super().__init__(problem)
        self.problem, self.problem_mark = problem, mark


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader with the config reader's limits: nodes as written and with every
    alias counted as the nodes it stands for (computed once per node, so an alias bomb is refused
    without being expanded), nesting depth (also through aliases), no alias inside the node it
    refers to, no key given twice."""

    def __init__(self, stream):
        super().__init__(stream)
        self._written = 0
        self._depth = 0
        self._sizes = {}  # id(node) -> (nodes with aliases expanded, levels), for finished nodes

    def compose_node(self, parent, index):
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            target = self.anchors.get(event.anchor)
            if target is not None and id(target) not in self._sizes:
                raise _Limited(f"the alias *{one_line(event.anchor, 40)} is inside the node it refers to",
                               event.start_mark)
            node = super().compose_node(parent, index)
            if self._depth + self._sizes[id(node)][1] > MAX_DEPTH:
                raise _Limited(f"nested more than {MAX_DEPTH} levels deep through the alias "
                               f"*{one_line(event.anchor, 40)}", event.start_mark)
            self._count(event.start_mark)
            return node
        self._count(event.start_mark)
        collection = isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent))
        if collection:
            self._depth += 1
            if self._depth > MAX_DEPTH:
                raise _Limited(f"nested more than {MAX_DEPTH} levels deep", event.start_mark)
        node = super().compose_node(parent, index)
        if collection:
            self._depth -= 1
            children = node.value if isinstance(node, yaml.SequenceNode) else \
                [n for pair in node.value for n in pair]
            sizes = [self._sizes[id(c)] for c in children]
            size = 1 + sum(s for s, _ in sizes)
            levels = 1 + max((h for _, h in sizes), default=0)
        else:
            size, levels = 1, 0
        if size > MAX_NODES:
            raise _Limited(f"more than {MAX_NODES} YAML nodes once its aliases are expanded "
                           "(an alias bomb?)", event.start_mark)
        self._sizes[id(node)] = (size, levels)
        return node

    def _count(self, mark):
        self._written += 1
        if self._written > MAX_NODES:
            raise _Limited(f"more than {MAX_NODES} YAML nodes", mark)

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            seen = set()
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    new = key not in seen
                except TypeError:
                    continue  # unhashable: PyYAML says so itself
                if not new:
                    raise _Limited(f"the key {show(key, 60)} is given twice", key_node.start_mark)
                seen.add(key)
        return super().construct_mapping(node, deep)


def read_text(path, what, follow=True, limit=MAX_BYTES):
    """The text of the regular UTF-8 file `path` of at most `limit` bytes; StudyError otherwise.
    A FIFO or device is refused before it is read (opened without blocking); follow=False: a
    symbolic link is refused too."""
    flags = os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW)
    try:
        fd = os.open(path, flags)
    except OSError as e:
        if not follow and lstat(path) is not None and stat.S_ISLNK(os.lstat(path).st_mode):
            raise StudyError(f"{path}: the {what} is a symbolic link, not a regular file") from None
        raise StudyError(f"{path}: cannot read the {what} ({e.strerror or e})") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise StudyError(f"{path}: the {what} is {file_kind(mode)}, not a regular file")
    with os.fdopen(fd, "rb") as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise StudyError(f"{path}: cannot read the {what} ({e.strerror or e})") from None
    if len(data) > limit:
        raise StudyError(f"{path}: the {what} has more than {limit} bytes (at most {limit})")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise StudyError(f"{path}: the {what} is not UTF-8 text (byte 0x{data[e.start]:02x} at offset {e.start})") from None


def load_yaml(text, path):
    """The YAML document `text` under the limits of a study file; StudyError naming `path`."""
    try:
        return yaml.load(text, Loader=_Loader)
    except _Limited as e:
        at = f" (line {e.problem_mark.line + 1})" if e.problem_mark is not None else ""
        raise StudyError(f"{path}: {e.problem}{at}") from None
    except yaml.YAMLError as e:
        where = getattr(e, "problem_mark", None)
        at = f" (line {where.line + 1})" if where is not None else ""
        problem = " ".join(str(getattr(e, "problem", None) or e).split())
        raise StudyError(f"{path}: not YAML{at}: {one_line(problem, 200)}") from None
    except (ValueError, RecursionError) as e:  # an integer of more than 4300 digits, ...
        raise StudyError(f"{path}: not a usable YAML document ({one_line(e, 120)})") from None
