"""The generated part of a hand-written report page: everything from the heading "## This run" on
is replaced by the new text (the page's hand-written head stays). Shared by latency_report.py and
soak_live_report.py."""

MARKER = "## This run"


def write_run_section(md, text):
    """Replaces the "## This run" section of page `md` (or appends it) with `text`, and prints it."""
    with open(md) as f:
        doc = f.read()
    doc = doc[: doc.index(MARKER)] if MARKER in doc else doc
    with open(md, "w") as f:
        f.write(doc.rstrip() + "\n\n" + text)
    print(text)
