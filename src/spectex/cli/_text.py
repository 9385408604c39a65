"""``spectex text``: Markov-model text, printed English as a 1-D texture."""

from __future__ import annotations

from . import _common

#: Largest corpus file read (its n-gram tables are built in memory, in Python).
MAX_CORPUS_BYTES = 64 << 20


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
    p.add_argument("--seed", type=_common.seed, default=0, help="random seed (default: 0)")
    p.add_argument("-o", "--output", type=_common.output_name, default=None,
                   help="write the text to this file instead of standard output")
    p.set_defaults(func=run)


def run(args) -> int | None:
    from pathlib import Path

    from spectex._limits import MAX_TEXT_LENGTH
    from spectex._output import note_input, plan_output, write_text

    if args.length > MAX_TEXT_LENGTH:
        raise ValueError(f"--length must be at most {MAX_TEXT_LENGTH} symbols (the text is built in memory), "
                         f"got {args.length}")
    if args.output is not None:  # a file, or a device or pipe such as /dev/stdout (written in place)
        plan_output(args.output, inputs=[args.corpus], stream=True)
    else:
        _common.require_stdout("the text would be lost; give -o FILE")
    note_input(args.corpus)
    size = Path(args.corpus).stat().st_size
    if size > MAX_CORPUS_BYTES:
        raise ValueError(f"corpus '{args.corpus}' is {size} bytes, over the limit of {MAX_CORPUS_BYTES} bytes "
                         f"({MAX_CORPUS_BYTES >> 20} MiB: the model is built in memory)")
    data = Path(args.corpus).read_bytes()
    if b"\x00" in data:
        raise ValueError(f"corpus is not a text file (it holds NUL bytes): '{args.corpus}'")
    corpus = data.decode("utf-8", errors="replace")
    from spectex.synthesis import markov_text  # the synthesis package imports numba: after every check

    with _common.Progress("markov text") as bar:
        text = markov_text(corpus, unit=args.unit, order=args.order, length=args.length, rng=args.seed,
                           progress=bar)
    if args.output is None:
        print(text)
    else:
        target = write_text(args.output, text + "\n", inputs=[args.corpus])
        if not target.stream:
            _common.report(f"wrote {args.output} ({args.length} {args.unit}s, order {args.order})")
    return 0
