"""The height options ``export-flight`` and ``import-flight`` share: which heights a
flight file holds (``--altitude relative|absolute``), the take-off height and the offset
added to absolute heights.

``--height`` (``import-flight``'s former name) and ``amsl`` (``export-flight``'s former
word for ``absolute``) are kept as aliases because scripts use them; both commands accept
either spelling."""

from __future__ import annotations

import argparse

#: the words ``--altitude`` takes: heights above the take-off point, or absolute heights
#: (above sea level, the project's Z plus ``--height-offset-m``)
ALTITUDE_WORDS = ("relative", "absolute")

#: former words, still accepted: alias → word
ALTITUDE_ALIASES = {"amsl": "absolute"}


def altitude_word(text: str) -> str:
    """The ``--altitude`` word ``text`` names (an alias gives its word); an unknown word
    is returned as given, for argparse's ``choices`` to refuse."""
    return ALTITUDE_ALIASES.get(text, text)


def add_height_arguments(parser: argparse.ArgumentParser, *, default: str,
                         offset_example: str) -> None:
    """Add ``--altitude`` (alias ``--height``; ``args.altitude`` is ``relative`` or
    ``absolute``, ``default`` when not given), ``--takeoff-height-m`` (m, ``None`` by
    default) and ``--height-offset-m`` (m, default 0; ``offset_example`` says what it is
    for in this command) to ``parser``."""
    parser.add_argument("--altitude", "--height", dest="altitude", type=altitude_word,
                        choices=ALTITUDE_WORDS, default=default,
                        help="relative: heights above the take-off point (DJI's "
                             "RelativeAltitude); absolute: the project's Z + "
                             f"--height-offset-m (default {default}; --height and the word "
                             "amsl are the former spellings, still accepted)")
    parser.add_argument("--takeoff-height-m", type=float, default=None,
                        help="project height Z of the take-off point, for relative heights "
                             "(default: the terrain below the first photo)")
    parser.add_argument("--height-offset-m", type=float, default=0.0,
                        help=f"added to every absolute height (m), e.g. {offset_example} "
                             "(default 0)")
