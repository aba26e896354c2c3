"""Frozen dataclasses made without ``exec``: :func:`frozen` is ``@dataclass(frozen=True)``.

``dataclasses.dataclass`` writes each method it adds (``__init__``, ``__repr__``,
``__eq__``, ``__hash__``, ``__setattr__``, ``__delattr__``) as source text and compiles it,
one ``exec`` a method up to Python 3.12 (0.1-0.2 ms each, about 0.7 ms a class): with the
package's 14 value classes that was most of what importing the fronts cost.  Here
``dataclass`` only collects the fields, with every option that generates code off (so
``dataclasses.fields``, ``replace``, ``asdict``, ``is_dataclass`` and ``__match_args__``
work as before), and the methods are closures over the field names, doing what the
generated ones do (Python 3.11's: ``__eq__`` and ``__hash__`` compare and hash the tuple
of the fields; assigning or deleting a field raises ``FrozenInstanceError``);
``__dataclass_params__`` is then set to what ``@dataclass(frozen=True, eq=eq)`` records, so
that a dataclass deriving from one of these must be frozen too, as before.

``__init__`` takes the fields as the generated one does (positionally or by name, in field
order, defaults from the class body), calls ``__post_init__`` if the class has one, and
carries the generated one's signature (``inspect.signature``); a call that does not fit it
raises ``TypeError`` (the message is ``inspect``'s).  It fills the instance ``__dict__``
in one update, which is what ``object.__setattr__`` per field does when no field name is a
data descriptor of the class (checked here; the lazy results' fields are non-data
descriptors, set on the class after it is made).
"""
from __future__ import annotations

import dataclasses
from dataclasses import MISSING, FrozenInstanceError
from operator import attrgetter
from reprlib import recursive_repr


def frozen(cls=None, /, *, eq: bool = True):
    """``@dataclass(frozen=True, eq=eq)`` without generated source (see the module)."""
    if cls is None:
        return lambda c: frozen(c, eq=eq)
    dataclasses.dataclass(cls, init=False, repr=False, eq=False)
    fields = dataclasses.fields(cls)
    qualname = cls.__qualname__
    _init(cls, [f for f in fields if f.init], qualname)
    _add(cls, "__repr__", _repr([f.name for f in fields if f.repr]), qualname)
    if eq:
        # a __hash__ of the class body's own (None only where its own __eq__ set it) stays
        explicit = cls.__dict__.get("__hash__", MISSING)
        add_hash = explicit is MISSING or (explicit is None and "__eq__" in cls.__dict__)
        _add(cls, "__eq__", _eq(_key(tuple(f.name for f in fields if f.compare))), qualname)
        if add_hash:
            hashed = tuple(f.name for f in fields if (f.compare if f.hash is None else f.hash))
            cls.__hash__ = _hash(_key(hashed), qualname)
    _frozen_attributes(cls, tuple(f.name for f in fields), qualname)
    params = cls.__dataclass_params__
    params.init = params.repr = True
    params.eq = eq
    params.frozen = True
    return cls


def _add(cls, name, fn, qualname):
    """Set ``cls.name = fn`` unless the class body defines it (as dataclass does)."""
    if name not in cls.__dict__:
        fn.__name__ = name
        fn.__qualname__ = f"{qualname}.{name}"
        setattr(cls, name, fn)


def _init(cls, fields, qualname):
    for f in fields:
        if f.default_factory is not MISSING or getattr(f, "kw_only", False) is True:
            raise TypeError(f"{qualname}.{f.name}: frozen() takes plain fields with plain defaults")
        if hasattr(type(cls.__dict__.get(f.name)), "__set__"):
            raise TypeError(f"{qualname}.{f.name} is a data descriptor of the class")
    names = tuple(f.name for f in fields)
    n = len(names)
    r = sum(f.default is MISSING for f in fields)  # the fields without a default come first
    if any(f.default is MISSING for f in fields[r:]):
        raise TypeError(f"{qualname}: a field without a default follows one with a default")
    # a call's arguments: every field in order, its default first (in __dict__, the order of
    # the generated __init__'s assignments), then the positional ones, then the keywords
    start = dict.fromkeys(names)
    start.update((f.name, f.default) for f in fields[r:])
    keywords = [frozenset(names[k:]) for k in range(n + 1)]  # what may still come by keyword
    needed = [frozenset(names[k:r]) for k in range(n + 1)]  # and what must
    post_init = hasattr(cls, "__post_init__")

    def __init__(self, *args, **kwargs):
        d = self.__dict__
        k = len(args)
        if k == n and not kwargs:
            d.update(zip(names, args))
        elif k <= n and kwargs.keys() <= keywords[k] and needed[k] <= kwargs.keys():
            d.update(start)
            d.update(zip(names, args))
            d.update(kwargs)
        else:  # too many, unknown, repeated or missing arguments: say which
            __init__.__signature__.bind(self, *args, **kwargs)
            raise TypeError(f"{qualname}.__init__() takes the fields {names}")
        if post_init:
            self.__post_init__()

    import inspect  # (numpy imports it: nothing to load)

    P = inspect.Parameter
    __init__.__signature__ = inspect.Signature(
        [P("self", P.POSITIONAL_OR_KEYWORD)]
        + [P(f.name, P.POSITIONAL_OR_KEYWORD, annotation=f.type,
            default=P.empty if f.default is MISSING else f.default) for f in fields],
        return_annotation=None)
    _add(cls, "__init__", __init__, qualname)


def _key(names):
    """A function of an instance: the tuple of those fields."""
    if len(names) == 1:
        get = attrgetter(names[0])
        return lambda self: (get(self),)
    return attrgetter(*names) if names else lambda self: ()


def _repr(names):
    @recursive_repr()
    def __repr__(self):
        return (self.__class__.__qualname__ + "("
                + ", ".join([f"{name}={getattr(self, name)!r}" for name in names]) + ")")
    return __repr__


def _eq(key):
    def __eq__(self, other):
        if other.__class__ is self.__class__:
            return key(self) == key(other)
        return NotImplemented
    return __eq__


def _hash(key, qualname):
    def __hash__(self):
        return hash(key(self))
    __hash__.__qualname__ = f"{qualname}.__hash__"
    return __hash__


def _frozen_attributes(cls, names, qualname):
    """``__setattr__`` and ``__delattr__`` that refuse every field (and, on the class itself,
    every name), as a frozen dataclass's do."""
    for name in ("__setattr__", "__delattr__"):
        if name in cls.__dict__:
            raise TypeError(f"Cannot overwrite attribute {name} in class {cls.__name__}")
    names = frozenset(names)

    def __setattr__(self, name, value):
        if type(self) is cls or name in names:
            raise FrozenInstanceError(f"cannot assign to field {name!r}")
        super(cls, self).__setattr__(name, value)

    def __delattr__(self, name):
        if type(self) is cls or name in names:
            raise FrozenInstanceError(f"cannot delete field {name!r}")
        super(cls, self).__delattr__(name)

    _add(cls, "__setattr__", __setattr__, qualname)
    _add(cls, "__delattr__", __delattr__, qualname)
