"""The command line the request generators share: DIR N [FIRST_SEED], request k from seed
FIRST_SEED + k alone, written to DIR/<prefix>-<seed>.json."""
import json
import os
import sys


def write_requests(usage, prefix, request):
    if len(sys.argv) < 3:
        sys.exit(usage)
    out, n = sys.argv[1], int(sys.argv[2])
    first = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    os.makedirs(out, exist_ok=True)
    for seed in range(first, first + n):
        with open(os.path.join(out, "%s-%d.json" % (prefix, seed)), "w") as f:
            json.dump(request(seed), f)
