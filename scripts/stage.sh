#!/usr/bin/env bash
# Mark the start of a stage of `make test`: appends "<name> <epoch seconds>" to $POMKIT_STAGES
# when it is set (.ci/run sets it and prints each stage's time at the end); a no-op otherwise.
if [ -n "${POMKIT_STAGES:-}" ]; then
    echo "$1 $(date +%s)" >> "$POMKIT_STAGES"
fi
