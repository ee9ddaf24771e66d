"""product.py - how the per-surface picture and distortion scripts end.

guarded(work, out): runs work(); if it raises (a map it cannot match to its input, a failed
`authalic texture`, a bad attribute file), OUT is left empty and the message goes to OUT.error and
stderr, and the script still exits 0: one surface's picture must not stop the cohort, and
cohort.tsv's `notes` column and cohort.md show what went wrong. A success removes an old OUT.error.
Missing Python modules fail before this (at import), loudly: that is the machine, not the surface.
"""
import os
import sys
import traceback


def guarded(work, out):
    err = out + ".error"
    try:
        work()
    except Exception as e:  # noqa: BLE001 - any failure of this one product is reported, not raised
        msg = f"{os.path.basename(out)}: {type(e).__name__}: {e}".replace("\n", " ")
        traceback.print_exc()
        print(msg, file=sys.stderr)
        open(out, "wb").close()
        with open(err, "w") as fh:
            fh.write(msg + "\n")
        return 0
    if os.path.exists(err):
        os.remove(err)
    return 0
