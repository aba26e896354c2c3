"""lemke._frozen.frozen makes what @dataclass(frozen=True) makes (without compiling generated
methods): the same signature, fields, params, repr, equality, hashing, copies,
frozen attributes, argument errors and subclassing rules, on a class of each kind."""
import copy
import dataclasses
import inspect

import numpy as np
import pytest

import lemke
from lemke._frozen import frozen
from lemke._kinds import Kind


class _Base:
    __slots__ = ()


def _make(eq):
    class Value(_Base):
        """A value."""

        a: int
        b: "tuple[int, ...]"
        c: float = 1.5
        d: object = None

        def __post_init__(self):
            object.__setattr__(self, "a", int(self.a))

    Value.__qualname__ = f"Value{int(eq)}"
    return Value


def _behaviour(cls, eq):
    p = cls.__dataclass_params__
    x = cls(1.0, (2,), d=(3,))
    out = [str(inspect.signature(cls)), [(f.name, f.default) for f in dataclasses.fields(cls)],
           (p.init, p.repr, p.eq, p.order, p.unsafe_hash, p.frozen), cls.__match_args__,
           repr(x), x == cls(1, (2,), 1.5, (3,)), x == cls(1, (2,)), x.__eq__(5), list(vars(x)),
           dataclasses.replace(x, c=2.0), dataclasses.asdict(x), x == copy.copy(x)]
    if eq:
        out += [hash(x) == hash((1, (2,), 1.5, (3,))), copy.deepcopy(cls(1, (2,))) == cls(1, (2,))]
    for act in (lambda: setattr(x, "a", 2), lambda: delattr(x, "a"), lambda: setattr(x, "other", 2),
                lambda: cls(), lambda: cls(1, 2, 3, 4, 5), lambda: cls(1, 2, a=1), lambda: cls(1, 2, e=1)):
        with pytest.raises((TypeError, dataclasses.FrozenInstanceError)) as info:
            act()
        out.append((info.type.__name__, str(info.value) if info.type is not TypeError else ""))
    with pytest.raises(TypeError, match="cannot inherit non-frozen dataclass from a frozen one"):
        dataclasses.dataclass(type("Sub", (cls,), {"__annotations__": {"e": int}, "e": 0}))
    sub = dataclasses.dataclass(frozen=True)(type("Sub", (cls,), {"__annotations__": {"e": int}, "e": 0}))
    out.append(repr(sub(1, (2,), e=3)))
    return [str(v).replace(cls.__qualname__, "V") for v in out]


@pytest.mark.parametrize("eq", [True, False])
def test_frozen_is_the_frozen_dataclass(eq):
    made = frozen(_make(eq), eq=eq)
    reference = dataclasses.dataclass(frozen=True, eq=eq)(_make(eq))
    assert _behaviour(made, eq) == _behaviour(reference, eq)
    if not eq:
        assert made.__eq__ is _Base.__eq__ and made.__hash__ is _Base.__hash__


def test_frozen_refuses_what_it_does_not_make():
    class Factory:
        a: list = dataclasses.field(default_factory=list)

    with pytest.raises(TypeError, match="plain defaults"):
        frozen(Factory)

    class Setter:
        a: int

        def __setattr__(self, name, value):
            pass

    with pytest.raises(TypeError, match="Cannot overwrite attribute __setattr__"):
        frozen(Setter)


@pytest.mark.parametrize("cls", [lemke.WarmStart, lemke.Options, lemke.BoxWarmStart, lemke.GameBasis,
                                 Kind, lemke.LCPResult, lemke.QPResult, lemke.BLCPResult, lemke.MLCPResult,
                                 lemke.BimatrixResult, lemke.Certificate, lemke.WarmStartBatch,
                                 lemke.LCPBatchResult, lemke.BoxWarmStartBatch])
def test_the_value_classes_are_frozen_dataclasses(cls):
    assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen
    names = [f.name for f in dataclasses.fields(cls)]
    assert list(inspect.signature(cls).parameters) == names


def test_results_keep_their_fields_through_replace():
    res = lemke.solve_qp(np.eye(2), -np.ones(2), G=np.ones((1, 2)), h=np.ones(1))
    again = dataclasses.replace(res, pivots=-1)
    assert again.pivots == -1 and again.x is res.x and again.status is res.status
    assert list(vars(again)) == [f.name for f in dataclasses.fields(lemke.QPResult)]
    with pytest.raises(dataclasses.FrozenInstanceError):
        again.x = None


def test_frozen_adds_hash_where_dataclass_does():
    def bodies():
        yield {"__hash__": None}  # unhashable on purpose: stays so
        yield {"__eq__": lambda self, other: True}  # (its __hash__ None): hashed by the fields
        yield {"__hash__": lambda self: 7}  # its own: kept

    for made_body, reference_body in zip(bodies(), bodies()):
        made = frozen(type("V", (), {"__annotations__": {"a": int}, **made_body}))
        reference = dataclasses.dataclass(frozen=True)(type("V", (), {"__annotations__": {"a": int}, **reference_body}))
        assert (made.__hash__ is None) == (reference.__hash__ is None)
        if reference.__hash__ is not None:
            assert hash(made(1)) == hash(reference(1))
