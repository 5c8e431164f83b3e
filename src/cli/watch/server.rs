//! The viewer's HTTP server, on 127.0.0.1 only, one thread per request (`tiny_http`):
//!
//! | path | response |
//! |---|---|
//! | `/` | the viewer page (`viewer.html`, built into the binary; it fetches nothing from elsewhere) |
//! | `/events` | Server-Sent Events: the view's JSON ([`super::view::View::event_json`]) at once and after every change |
//! | `/frame.bin` | the latest frame: little-endian `f32` RGB per pixel, then a `u32` sample count per pixel |
//! | `/image.png`, `/image.exr` | the latest frame as a download (PNG at the scene's exposure, linear EXR) |
//!
//! Anything else is 404; only GET is answered.

use super::view::Shared;
use std::io::Write;
use std::sync::Arc;
use std::time::Duration;
use tiny_http::{Header, Method, Request, Response, Server};

/// The viewer page.
const PAGE: &str = include_str!("viewer.html");

/// How long an event stream stays silent before a comment line checks that the browser is still there.
const KEEPALIVE: Duration = Duration::from_secs(10);

/// Bind `127.0.0.1:port` (0: a free port); the server and its address.
pub fn bind(port: u16) -> anyhow::Result<(Arc<Server>, std::net::SocketAddr)> {
    let server = Server::http(("127.0.0.1", port))
        .map_err(|e| anyhow::anyhow!("prism watch: cannot listen on 127.0.0.1:{port}: {e}"))?;
    let addr =
        server.server_addr().to_ip().ok_or_else(|| anyhow::anyhow!("prism watch: the server has no IP address"))?;
    Ok((Arc::new(server), addr))
}

/// Answer requests until the process ends (each on its own thread: event streams stay open).
pub fn serve(server: Arc<Server>, shared: Arc<Shared>) {
    for request in server.incoming_requests() {
        let shared = shared.clone();
        std::thread::spawn(move || handle(request, &shared));
    }
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("a valid header")
}

fn handle(request: Request, shared: &Shared) {
    if request.method() != &Method::Get {
        let _ = request.respond(Response::from_string("only GET").with_status_code(405));
        return;
    }
    let path = request.url().split('?').next().unwrap_or("").to_string();
    let frame = || shared.lock().frame.clone();
    let result = match path.as_str() {
        "/" | "/index.html" => {
            request.respond(Response::from_string(PAGE).with_header(header("Content-Type", "text/html; charset=utf-8")))
        }
        "/events" => {
            events(request, shared);
            Ok(())
        }
        "/frame.bin" => match frame() {
            Some(f) => request.respond(
                Response::from_data(f.to_bytes())
                    .with_header(header("Content-Type", "application/octet-stream"))
                    .with_header(header("Cache-Control", "no-store")),
            ),
            None => request.respond(Response::from_string("no image yet").with_status_code(404)),
        },
        "/image.png" | "/image.exr" => match frame() {
            Some(f) => {
                let img = f.image();
                let (bytes, kind) = if path.ends_with("png") {
                    (prism_core::io::png_bytes(&img, f.exposure), "image/png")
                } else {
                    (prism_core::io::exr_bytes(&img), "image/x-exr")
                };
                match bytes {
                    Ok(b) => {
                        request.respond(Response::from_data(b).with_header(header("Content-Type", kind)).with_header(
                            header("Content-Disposition", &format!("attachment; filename=\"prism{}\"", &path[6..])),
                        ))
                    }
                    Err(e) => request.respond(Response::from_string(e).with_status_code(500)),
                }
            }
            None => request.respond(Response::from_string("no image yet").with_status_code(404)),
        },
        _ => request.respond(Response::from_string("not found").with_status_code(404)),
    };
    let _ = result;
}

/// An event stream: the current view, then one event per change, until the browser goes away.
fn events(request: Request, shared: &Shared) {
    let mut w = request.into_writer();
    let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\r\n";
    if w.write_all(head.as_bytes()).and_then(|()| w.flush()).is_err() {
        return;
    }
    let mut view = shared.lock().clone();
    loop {
        let message = format!("data: {}\n\n", view.event_json());
        if w.write_all(message.as_bytes()).and_then(|()| w.flush()).is_err() {
            return;
        }
        let seen = view.version;
        loop {
            view = shared.wait_change(seen, KEEPALIVE);
            if view.version != seen {
                break;
            }
            if w.write_all(b": keepalive\n\n").and_then(|()| w.flush()).is_err() {
                return;
            }
        }
    }
}
