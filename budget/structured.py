"""JSON and YAML a user writes (scenarios, noise models, mappings, acceptance specs), read with
limits, each refused with an :class:`~budget.errors.InputError` naming the file: at most
:data:`MAX_DEPTH` levels of nesting and :data:`MAX_NODES` values (YAML aliases counted as often
as they are expanded, so a "billion laughs" file is refused before it is built), integers of at
most :data:`MAX_INT_DIGITS` digits, no duplicate keys; the extension decides the reader."""

from __future__ import annotations

import json
import re
from pathlib import Path

from .errors import InputError
from .fileio import read_text

#: JSON/YAML limits: nesting depth, number of values (aliases expanded), digits of an integer.
MAX_DEPTH = 64
MAX_NODES = 200_000
MAX_INT_DIGITS = 30


def _check_tree(data, path) -> None:
    """Depth, size and integer limits of parsed JSON (iterative: no recursion on deep input)."""
    stack = [(data, 1)]
    nodes = 0
    while stack:
        obj, depth = stack.pop()
        nodes += 1
        if nodes > MAX_NODES:
            raise InputError(f"more than {MAX_NODES:,} values", file=path,
                             expected="a small configuration file")
        if depth > MAX_DEPTH:
            raise InputError(f"nested more than {MAX_DEPTH} levels deep", file=path,
                             expected="a flat configuration mapping")
        if isinstance(obj, dict):
            stack.extend((v, depth + 1) for v in obj.values())
        elif isinstance(obj, list):
            stack.extend((v, depth + 1) for v in obj)
        elif isinstance(obj, int) and not isinstance(obj, bool) and abs(obj) >= 10 ** MAX_INT_DIGITS:
            raise InputError(f"integer with more than {MAX_INT_DIGITS} digits", file=path,
                             value=obj, expected="a number of sensible size")


#: A number as JSON writes it (and .inf / .nan, which the models refuse with their own words).
_PLAIN_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|[-+]?\.(inf|Inf|INF)|\.(nan|NaN|NAN)")


def _yaml_node(text: str, path):
    """Compose the YAML document and check depth and *expanded* size before constructing it."""
    import yaml

    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _check_yaml_nodes(node, path)
        return loader.construct_document(node)
    finally:
        loader.dispose()


def _check_yaml_nodes(root, path) -> None:
    import yaml

    size: dict[int, int] = {}
    # iterative post-order walk; shared (aliased) nodes are sized once and counted per use
    stack = [(root, 1, False)]
    on_path: set[int] = set()
    while stack:
        node, depth, done = stack.pop()
        key = id(node)
        if done:
            on_path.discard(key)
            kids = _yaml_children(node)
            size[key] = 1 + sum(size[id(k)] for k in kids)
            if size[key] > MAX_NODES:
                raise InputError(f"expands to more than {MAX_NODES:,} values (YAML aliases?)",
                                 file=path, expected="a small configuration file without alias bombs")
            continue
        if key in size:
            continue
        if depth > MAX_DEPTH:
            raise InputError(f"nested more than {MAX_DEPTH} levels deep", file=path,
                             expected="a flat configuration mapping")
        if key in on_path:
            raise InputError("recursive YAML alias", file=path, expected="a tree of values")
        if isinstance(node, yaml.ScalarNode):
            if node.tag.endswith(":int") and len(node.value.lstrip("+-0")) > MAX_INT_DIGITS:
                raise InputError(f"integer with more than {MAX_INT_DIGITS} digits", file=path,
                                 value=node.value, expected="a number of sensible size")
            text = node.value.strip()
            if node.tag.endswith((":int", ":float")) and (not _PLAIN_NUMBER.fullmatch(text) or (
                    node.tag.endswith(":int") and re.fullmatch(r"[-+]?0\d+", text))):
                # YAML 1.1 reads 1:40 as 100 (base 60), 0x64 as 100, 1_000 as 1000, 012 as 10
                raise InputError(f"a number in a form YAML 1.1 reads as another value (line "
                                 f"{node.start_mark.line + 1})", file=path, value=node.value,
                                 expected="a plain decimal number (digits, a decimal point, an exponent), or the "
                                          "value in quotes if it is text")
            size[key] = 1
            continue
        if isinstance(node, yaml.MappingNode):
            _check_yaml_keys(node, path)
        on_path.add(key)
        stack.append((node, depth, True))
        stack.extend((k, depth + 1, False) for k in _yaml_children(node) if id(k) not in size)


def _duplicate_key(key, path, where: str = "") -> InputError:
    return InputError(f"key given twice{where}: a reader would silently keep one of the values",
                      file=path, field=str(key), expected="each key once per mapping")


def _check_yaml_keys(node, path) -> None:
    """Refuse a mapping that gives the same plain key twice (the YAML merge key ``<<`` excepted)."""
    import yaml

    seen: dict[str, int] = {}
    for k, _ in node.value:
        if not isinstance(k, yaml.ScalarNode) or k.tag == "tag:yaml.org,2002:merge":
            continue
        line = k.start_mark.line + 1
        if k.value in seen:
            raise _duplicate_key(k.value, path, f" (lines {seen[k.value]} and {line})")
        seen[k.value] = line


def _json_object(pairs, path):
    """``object_pairs_hook`` of :func:`json.loads`: a dict, refusing a key given twice."""
    out = {}
    for k, v in pairs:
        if k in out:
            raise _duplicate_key(k, path)
        out[k] = v
    return out


def _yaml_children(node) -> list:
    import yaml

    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [x for pair in node.value for x in pair]
    return []


def parse_structured(text: str, *, yaml_syntax: bool, path=None):
    """Parse JSON (or YAML) text with the limits of this module; errors as :class:`InputError`."""
    import yaml

    kind = "YAML" if yaml_syntax else "JSON"
    try:
        data = (_yaml_node(text, path) if yaml_syntax
                else json.loads(text, object_pairs_hook=lambda pairs: _json_object(pairs, path)))
    except InputError:
        raise
    except (json.JSONDecodeError, yaml.YAMLError) as err:
        # PyYAML's first line names the construct only ("while scanning for the next token"):
        # the problem and its line and column are in its mark
        mark = getattr(err, "problem_mark", None)
        where = (f" (line {mark.line + 1}, column {mark.column + 1}: {getattr(err, 'problem', '')})"
                 if mark is not None else "")
        raise InputError(f"not valid {kind}: {str(err).splitlines()[0][:200]}{where}", file=path) from None
    except RecursionError:
        raise InputError(f"nested too deeply to read (more than {MAX_DEPTH} levels expected)",
                         file=path, expected="a flat configuration mapping") from None
    except ValueError as err:  # e.g. an integer beyond Python's 4300-digit conversion limit
        msg = ("an integer has more than 4300 digits" if "digits" in str(err)
               else f"not valid {kind}: {str(err).splitlines()[0][:120]}")
        raise InputError(msg, file=path, expected="numbers of sensible size") from None
    _check_tree(data, path)  # for YAML the alias-expanded size was bounded before construction
    return data


def _reads_as_yaml_mapping(text: str, path) -> bool:
    """True if ``text`` (not valid JSON) is a YAML block mapping (``key: value`` lines), read with
    this module's limits; JSON with a slip (a trailing comma) is flow YAML too, and is not meant."""
    if text.lstrip("\ufeff \t\r\n").startswith(("{", "[")):
        return False
    try:
        return isinstance(parse_structured(text, yaml_syntax=True, path=path), dict)
    except InputError:
        return False


def read_structured(path: str | Path, what: str, max_bytes: int = 10_000_000) -> dict:
    """Read a JSON or YAML mapping (by suffix; YAML also reads JSON) for ``what`` (e.g.
    "a scenario"); a missing, empty, malformed, too deep/large or non-mapping file raises
    :class:`InputError`."""
    path = Path(path)
    text = read_text(path, max_bytes=max_bytes, expected=f"{what} JSON/YAML file")
    is_yaml = path.suffix.lower() in (".yaml", ".yml")
    try:
        data = parse_structured(text, yaml_syntax=is_yaml, path=path)
    except InputError as err:
        if is_yaml or not err.reason.startswith("not valid JSON") or not _reads_as_yaml_mapping(text, path):
            raise
        # YAML in a file whose name says JSON (or nothing): which reader runs follows the extension
        suffix = path.suffix or "no extension"
        raise InputError(f"{err.reason}: the file holds YAML, but a file named {suffix} is read as JSON",
                         file=path, expected="a .yaml or .yml name for YAML (rename the file), or JSON "
                         "text; the extension decides the reader: .yaml and .yml are read as YAML, "
                         ".json and any other as JSON") from None
    if not isinstance(data, dict):
        raise InputError(f"{what} must be a mapping of keys to values", file=path,
                         expected="a JSON object / YAML mapping")
    return data
