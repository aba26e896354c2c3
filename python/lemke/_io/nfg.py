"""Gambit's strategic-form game files (``.nfg``), both versions, for two-player games.

The layout (Gambit's documentation, "Game representation formats"): whitespace is not
significant; text is in double quotes (``\\"`` inside); numbers are integers, decimals or
rationals ``p/q``.  The prologue is ``NFG 1 R "title" { "player 1" "player 2" }``, then
either

- the **payoff version**: ``{ m n }`` (the numbers of strategies), an optional comment
  string, then the payoffs as a flat list, both players' payoffs for each strategy profile
  in turn, the first player's strategy changing fastest: ``A[0,0] B[0,0] A[1,0] B[1,0] ...``;
  or
- the **outcome version**: ``{ { "s1" "s2" ... } { "t1" ... } }`` (the strategies' names),
  an optional comment, a list of outcomes ``{ { "name" a, b } ... }`` (commas optional),
  then one outcome number per profile in the same order (1-based; 0 is the null outcome,
  paying 0 to both).

A file with the strategies named but a flat payoff list (as some of Gambit's own files have)
is read as the payoff version.  Only games with two players are accepted.  Exact numbers
(1/3) are rounded to the nearest float.
"""
from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np

from .._validate import article
from .common import MAX_ENTRIES, BadFile, ProblemFormatError, make_problem

__all__ = ["read_nfg"]

KINDS = ("bimatrix",)  # the kinds of problem this format holds (read only)
(BIMATRIX,) = KINDS


def read(data: bytes, path):
    """The game in an ``.nfg`` file's bytes as a Problem (for :func:`lemke.read_problem`)."""
    A, B = parse_nfg(data.decode("utf-8", errors="replace"))
    return make_problem(BIMATRIX, {"A": A, "B": B}, path, "Gambit .nfg")


def write(problem, fh) -> None:
    """Write a game in the payoff version (the first player's strategy changing fastest)."""
    m, n = problem.A.shape
    pay = " ".join(f"{float(problem.A[i, j])!r} {float(problem.B[i, j])!r}" for j in range(n) for i in range(m))
    name = problem.name.replace("\\", "\\\\").replace('"', '\\"')
    fh.write(f'NFG 1 R "{name}" {{ "Player 1" "Player 2" }} {{ {m} {n} }}\n\n{pay}\n'.encode("utf-8"))


def read_nfg(path) -> tuple[np.ndarray, np.ndarray]:
    """The payoffs ``(A, B)`` (row player's, column player's; both m x n float arrays) of the
    two-player game in the ``.nfg`` file ``path``.

    Raises
    ------
    ProblemFormatError
        When the file cannot be read or is not a valid two-player ``.nfg`` file; its message
        is one line naming the file.
    """
    try:
        text = Path(path).read_bytes().decode("utf-8", errors="replace")
    except OSError as err:
        raise ProblemFormatError(path, f"cannot read the file: {err.strerror or err}") from err
    try:
        return parse_nfg(text)
    except BadFile as err:
        raise ProblemFormatError(path, str(err)) from None


class _Tokens:
    """The file as tokens: ``{``, ``}``, quoted strings (kept as ``('str', text)``) and
    words; commas are separators."""

    def __init__(self, text: str):
        self.items: list = []
        i, n = 0, len(text)
        while i < n:
            c = text[i]
            if c.isspace() or c == ",":
                i += 1
            elif c in "{}":
                self.items.append(c)
                i += 1
            elif c == '"':
                j = i + 1
                chars = []
                while j < n and text[j] != '"':
                    if text[j] == "\\" and j + 1 < n:
                        j += 1
                    chars.append(text[j])
                    j += 1
                if j >= n:
                    raise BadFile("a quoted text is not closed")
                self.items.append(("str", "".join(chars)))
                i = j + 1
            else:
                j = i
                while j < n and not (text[j].isspace() or text[j] in '{},"'):
                    j += 1
                self.items.append(text[i:j])
                i = j
        self.pos = 0

    def peek(self):
        return self.items[self.pos] if self.pos < len(self.items) else None

    def next(self, what: str):
        tok = self.peek()
        if tok is None:
            raise BadFile(f"the file ends where {what} was expected")
        self.pos += 1
        return tok

    def expect(self, tok: str, what: str):
        got = self.next(what)
        if got != tok:
            raise BadFile(f"expected {what}, found {_show(got)}")

    def string(self, what: str) -> str:
        tok = self.next(what)
        if not isinstance(tok, tuple):
            raise BadFile(f"expected {what} (a quoted text), found {_show(tok)}")
        return tok[1]

    def names(self, what: str) -> int:
        """Read quoted names up to the closing ``}`` (consumed); returns how many."""
        count = 0
        while self.peek() != "}":
            self.string(what)
            count += 1
        self.pos += 1
        return count

    def optional_string(self):
        if isinstance(self.peek(), tuple):
            self.pos += 1


def _show(tok) -> str:
    if isinstance(tok, tuple):
        return f'the text "{tok[1][:30]}"'
    return repr(tok[:30])


def _number(tok, what: str) -> float:
    if isinstance(tok, tuple) or tok in ("{", "}"):
        raise BadFile(f"expected {what} (a number), found {_show(tok)}")
    try:
        value = float(Fraction(tok))
    except (ValueError, ZeroDivisionError, OverflowError):
        raise BadFile(f"{what} {tok[:30]!r} is not a number") from None
    if not np.isfinite(value):
        raise BadFile(f"{what} {tok[:30]!r} is not finite")
    return value


def _count(tok, what: str) -> int:
    if isinstance(tok, tuple) or not tok.isdigit() or int(tok) < 1:
        raise BadFile(f"{what} must be a positive integer, found {_show(tok)}")
    return int(tok)


def parse_nfg(text: str) -> tuple[np.ndarray, np.ndarray]:
    """:func:`read_nfg` on the file's text (raises ``BadFile``)."""
    t = _Tokens(text)
    if t.peek() != "NFG":
        raise BadFile("not a Gambit strategic-form file: it does not start with 'NFG'")
    t.pos += 1
    if t.next("the version") != "1":
        raise BadFile("only version 1 of the .nfg format is known")
    if t.next("the letter R or D") not in ("R", "D"):
        raise BadFile("expected the letter R after the version")
    t.string("the title")
    t.expect("{", "'{' before the players' names")
    players = t.names("a player's name")
    if players != 2:
        raise BadFile(f"the game has {players} players; only two-player (bimatrix) games are supported")
    t.expect("{", "'{' before the strategies")
    sizes = []
    named = t.peek() == "{"
    while t.peek() != "}":
        if named:
            t.expect("{", "'{' before a player's strategy names")
            k = t.names("a strategy's name")
            if k == 0:
                raise BadFile(f"player {len(sizes) + 1} has no strategies")
            sizes.append(k)
        else:
            sizes.append(_count(t.next("a number of strategies"), "a number of strategies"))
    t.pos += 1
    if len(sizes) != 2:
        raise BadFile(f"{len(sizes)} strategy counts for 2 players")
    m, n = sizes
    if m * n > MAX_ENTRIES:
        raise BadFile(f"the game is {m} x {n}, too large (limit {MAX_ENTRIES} profiles)")
    t.optional_string()  # the comment
    if named and t.peek() == "{":
        values = _outcome_payoffs(t, m * n)
    else:
        values = [_number(t.next("a payoff"), "a payoff") for _ in range(2 * m * n)]
    if t.peek() is not None:
        raise BadFile(f"unexpected {_show(t.peek())} after the {2 * m * n} payoffs of {article(m)} {m} x {n} game")
    pay = np.array(values, dtype=np.float64).reshape(n, m, 2)  # profile order: row fastest
    return np.ascontiguousarray(pay[:, :, 0].T), np.ascontiguousarray(pay[:, :, 1].T)


def _outcome_payoffs(t: _Tokens, profiles: int) -> list[float]:
    """The outcome list and the table of outcome numbers, as the flat payoff list."""
    t.expect("{", "'{' before the outcomes")
    outcomes = [(0.0, 0.0)]  # number 0: the null outcome
    while t.peek() != "}":
        t.expect("{", "'{' before an outcome")
        t.string("an outcome's name")
        a = _number(t.next("a payoff"), "a payoff")
        b = _number(t.next("a payoff"), "a payoff")
        t.expect("}", "'}' after an outcome's two payoffs")
        outcomes.append((a, b))
    t.pos += 1
    values = []
    for _ in range(profiles):
        tok = t.next("an outcome number")
        if isinstance(tok, tuple) or not tok.isdigit() or int(tok) >= len(outcomes):
            raise BadFile(f"outcome number {_show(tok)} is not one of 0..{len(outcomes) - 1}")
        values.extend(outcomes[int(tok)])
    return values
