"""``spectex text``: Markov-model text, printed English as a 1-D texture."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "text",
        help="generate text from a letter or word Markov model of a corpus",
        description=(
            "Train a letter or word n-gram model on a text file and sample from it "
            "(Shannon 1948). Order n conditions each symbol on the n before it; order 0 "
            "draws symbols independently with their corpus frequencies. For letters, runs "
            "of white space count as one space. The corpus is read as UTF-8 (undecodable "
            "bytes become U+FFFD)."
        ),
    )
    p.add_argument("corpus", type=_common.existing_file, help="training text file")
    p.add_argument("--unit", choices=("char", "word"), default="char",
                   help="symbol: letters or words (default: char)")
    p.add_argument("--order", type=_common.nonneg_int, default=3, help="Markov order, 0 to 12 (default: 3)")
    p.add_argument("--length", type=_common.nonneg_int, default=500,
                   help="number of letters or words to generate (default: 500)")
    p.add_argument("--seed", type=_common.nonneg_int, default=0, help="random seed (default: 0)")
    p.add_argument("-o", "--output", default=None, help="write the text to this file instead of standard output")
    p.set_defaults(func=run)


def run(args) -> int | None:
    from pathlib import Path

    from spectex.io import atomic_path
    from spectex.synthesis import markov_text

    data = Path(args.corpus).read_bytes()
    if b"\x00" in data:
        raise ValueError(f"corpus is not a text file (it holds NUL bytes): '{args.corpus}'")
    corpus = data.decode("utf-8", errors="replace")
    if args.output is not None:
        folder = Path(args.output).parent
        if str(folder) and not folder.is_dir():
            raise ValueError(f"output is in a folder that does not exist: '{args.output}'")
    with _common.Progress("markov text") as bar:
        text = markov_text(corpus, unit=args.unit, order=args.order, length=args.length, seed=args.seed,
                           progress=bar)
    if args.output is None:
        print(text)
    else:
        with atomic_path(args.output) as tmp:
            Path(tmp).write_text(text + "\n", encoding="utf-8")
        _common.report(f"wrote {args.output} ({args.length} {args.unit}s, order {args.order})")
    return 0
