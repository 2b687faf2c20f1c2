"""Checks Kubernetes Job manifests (JSON) against the batch/v1 Job schema of
the official Python client: each file is read into the client's V1Job model
(which refuses wrong types and missing required fields) and written back; a
field the schema does not know would be dropped, so the round trip must give
the file's content unchanged.

Usage: python3 check_job.py FILE.json...   (exit status 0 when all pass)
"""

import json
import sys

from kubernetes.client import ApiClient


def check(path):
    with open(path) as f:
        data = json.load(f)
    client = ApiClient()
    # The client's own deserialiser, as for a server response.
    job = client._ApiClient__deserialize(data, "V1Job")
    back = client.sanitize_for_serialization(job)
    if back != data:
        raise ValueError(
            "fields changed in the round trip through V1Job:\n  file: %s\n  model: %s"
            % (json.dumps(data, sort_keys=True), json.dumps(back, sort_keys=True))
        )
    spec = job.spec
    if spec.template.spec.containers[0].image is None:
        raise ValueError("the container has no image")
    return job


def main(paths):
    failed = False
    for path in paths:
        try:
            job = check(path)
            print("%s: valid batch/v1 Job %s (completions %s, mode %s)" % (
                path, job.metadata.name, job.spec.completions, job.spec.completion_mode))
        except Exception as e:  # report every file
            failed = True
            print("%s: INVALID: %s" % (path, e), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
