#!/usr/bin/env python3
# docs_test.cpp's stand-in for curl when curl is absent: the options that docs/service.md's
# examples use (-s, -X, -H, -d 'text' or -d @file) sent with urllib: the body and the headers
# curl sends (Content-Type, Accept, the -H ones), but for User-Agent; no proxy, as for loopback
import sys, urllib.request, urllib.error
args, method, headers, data, url = sys.argv[1:], None, {"Accept": "*/*", "User-Agent": "curl_fallback.py"}, None, None
i = 0
while i < len(args):
    a = args[i]
    if a == "-s":
        pass
    elif a == "-X":
        i += 1; method = args[i]
    elif a == "-H":
        i += 1; k, _, v = args[i].partition(":"); headers[k.strip()] = v.strip()
    elif a == "-d":
        i += 1; d = args[i]
        # curl -d @file sends the file without its carriage returns and newlines
        data = (open(d[1:], "rb").read().replace(b"\r", b"").replace(b"\n", b"") if d.startswith("@") else d.encode())
        headers.setdefault("Content-Type", "application/x-www-form-urlencoded")
    else:
        url = a
    i += 1
request = urllib.request.Request(url, data=data, headers=headers, method=method or ("POST" if data is not None else "GET"))
try:
    with urllib.request.build_opener(urllib.request.ProxyHandler({})).open(request) as answer:
        sys.stdout.buffer.write(answer.read())
except urllib.error.HTTPError as error:
    sys.stdout.buffer.write(error.read())
