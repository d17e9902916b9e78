#!/usr/bin/env python3
"""A client of `stepstone serve` using only Python's standard library.

Sends a behaviour matrix (rows = time steps, columns = the KB's channels) to a
knowledge base and prints its r_max: what `stepstone evolve` would add to a
policy shaped by that KB. Use it as a starting point for another simulator.

    stepstone serve kb.db --port 8080 &
    python3 examples/python/kb_client.py --url http://127.0.0.1:8080 --kb run --behaviour behaviour.json

behaviour.json holds {"behaviour": [[...], ...]} or a bare list of rows.
"""

import argparse
import json
import sys
import urllib.error
import urllib.parse
import urllib.request


def call(url, path, body=None, token=None):
    """GET (no body) or POST (a JSON body) one endpoint; returns the decoded JSON answer."""
    data = None if body is None else json.dumps(body).encode("utf-8")
    request = urllib.request.Request(url.rstrip("/") + path, data=data, method="GET" if body is None else "POST")
    request.add_header("Content-Type", "application/json")
    if token:
        request.add_header("Authorization", "Bearer " + token)
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            return json.load(response)
    except urllib.error.HTTPError as error:
        # the service explains every refusal in a JSON body
        try:
            message = json.load(error)["error"]
        except (ValueError, KeyError):
            message = error.reason
        raise SystemExit(f"kb_client: HTTP {error.code}: {message}")
    except urllib.error.URLError as error:
        raise SystemExit(f"kb_client: cannot reach {url}: {error.reason}")


def shape(url, kb, behaviour, token=None):
    """r_max and the per-segment matches of one behaviour matrix."""
    return call(url, f"/v1/kbs/{urllib.parse.quote(kb)}/shape", {"behaviour": behaviour}, token)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--url", default="http://127.0.0.1:8080", help="the server (default %(default)s)")
    parser.add_argument("--kb", required=True, help="the knowledge base's name (GET /v1/kbs lists them)")
    parser.add_argument("--behaviour", required=True, help="JSON file with the behaviour matrix")
    parser.add_argument("--token-file", help="file holding the bearer token, if the server needs one")
    parser.add_argument("--matches", action="store_true", help="also print every segment's match")
    args = parser.parse_args()

    with open(args.behaviour, encoding="utf-8") as f:
        document = json.load(f)
    behaviour = document["behaviour"] if isinstance(document, dict) else document
    token = None
    if args.token_file:
        with open(args.token_file, encoding="utf-8") as f:
            token = f.readline().strip()

    info = call(args.url, f"/v1/kbs/{urllib.parse.quote(args.kb)}", token=token)
    print(f"kb {info['name']}: {info['segments']} segments of {info['segment_width']} steps x "
          f"{info['channels']} channels, largest average reward {info['max_average_reward']!r}")
    answer = shape(args.url, args.kb, behaviour, token)
    if args.matches:
        for m in answer["matches"]:
            print(f"segment {m['segment']} step {m['step_start']}: kb segment {m['kb_segment_id']} "
                  f"distance {m['distance']!r} average reward {m['average_reward']!r}")
    print(f"r_max {answer['r_max']!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
