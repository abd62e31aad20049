"""`glview serve` behind a reverse proxy with TLS (docs/serve.md, "Behind a reverse proxy"):
Debian's nginx, started by the test with a self-signed certificate and the configuration the
docs give, and Debian's Chromium through it: the page loads over HTTPS, its socket is upgraded
through the proxy (wss://), the first frame shows and ArrowRight turns the view.
"""
import os
import shutil
import socket
import subprocess
import time

import pytest

from test_serve_page import CHROMIUM, FLAGS, Server, glview_bin, wait_still  # noqa: F401 (a fixture)

NGINX = "/usr/sbin/nginx"

# The server block of docs/serve.md, with the test's ports and files filled in.
CONF = """
daemon off;
master_process off;
pid {tmp}/nginx.pid;
error_log {tmp}/error.log warn;
events {{ worker_connections 256; }}
http {{
  access_log off;
  client_body_temp_path {tmp}/body;
  proxy_temp_path {tmp}/proxy;
  fastcgi_temp_path {tmp}/fastcgi;
  uwsgi_temp_path {tmp}/uwsgi;
  scgi_temp_path {tmp}/scgi;
  map $http_upgrade $connection_upgrade {{ default upgrade; '' close; }}
  server {{
    listen 127.0.0.1:{port} ssl;
    server_name localhost;
    ssl_certificate {tmp}/cert.pem;
    ssl_certificate_key {tmp}/key.pem;
    location / {{
      proxy_pass http://{upstream};
      proxy_http_version 1.1;
      proxy_set_header Host $http_host;
      proxy_set_header Upgrade $http_upgrade;
      proxy_set_header Connection $connection_upgrade;
      proxy_buffering off;
      proxy_read_timeout 300s;
    }}
  }}
}}
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_the_page_works_through_nginx_with_tls(glview_bin, tmp_path):
    if not os.path.exists(NGINX) or not shutil.which("openssl"):
        if os.environ.get("CI") == "true":
            pytest.fail("nginx or openssl is missing (scripts/deps.sh --browser installs them)")
        pytest.skip("nginx or openssl is missing (scripts/deps.sh --browser installs them)")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1",
                    "-subj", "/CN=localhost", "-keyout", tmp_path / "key.pem",
                    "-out", tmp_path / "cert.pem"], check=True, capture_output=True)
    port = free_port()
    public = f"https://localhost:{port}"
    server = Server(glview_bin, "--size", "320x240", "--public-url", public)
    upstream = next(line.split()[-1] for line in server.output if "listening on" in line)
    (tmp_path / "nginx.conf").write_text(CONF.format(tmp=tmp_path, port=port, upstream=upstream))
    nginx = subprocess.Popen([NGINX, "-c", tmp_path / "nginx.conf", "-p", tmp_path],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 10
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert nginx.poll() is None, nginx.stdout.read()
                assert time.monotonic() < deadline, "nginx did not listen"
                time.sleep(0.1)
        from playwright.sync_api import sync_playwright
        assert os.path.exists(CHROMIUM) or os.environ.get("CI") != "true"
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=FLAGS)
            page = browser.new_context(ignore_https_errors=True).new_page()
            errors = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            assert server.url.startswith(public + "/?token="), server.url
            assert page.goto(server.url).status == 200
            first = wait_still(page)
            # The socket went through the proxy: the page's address is the proxy's.
            assert page.evaluate("location.origin") == public
            page.keyboard.press("ArrowRight")
            h = wait_still(page, page.evaluate("window.glview.sent"))
            assert h["command"] != first["command"] and "--yaw 35" in h["command"], h["command"]
            assert not errors, errors
            browser.close()
    finally:
        nginx.terminate()
        nginx.wait(timeout=10)
        server.stop()
