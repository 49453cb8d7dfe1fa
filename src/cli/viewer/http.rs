//! The viewer's HTTP server: HTTP/1.1 `GET` (and `HEAD`) on 127.0.0.1, one thread per
//! connection, every response closed after it is sent but the event stream, which stays
//! open and gets the status after each build.
//!
//! Hand-written on `std::net` rather than a server crate: the viewer serves a handful
//! of fixed paths to one local browser, which needs request-line parsing, a few
//! headers and server-sent events, not a framework. Requests whose `Host` is not this
//! machine's loopback name are refused, so a web page elsewhere cannot reach the
//! viewer through a DNS name bound to 127.0.0.1 (DNS rebinding).

use std::io::{self, BufRead, BufReader, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::time::Duration;

use super::{assets, Shared, Viewer};

/// The longest request head read (request line and headers).
const MAX_HEAD: usize = 16 * 1024;
/// How long a connection may take to send its request.
const READ_TIMEOUT: Duration = Duration::from_secs(10);
/// How often an idle event stream sends a comment, which also finds closed streams.
const KEEPALIVE: Duration = Duration::from_secs(15);

/// Binds 127.0.0.1:`port` (0: any free port) and serves the viewer's paths on a
/// background thread. An error when the port cannot be bound (taken, or not allowed).
pub(crate) fn serve(port: u16) -> io::Result<Viewer> {
    let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port))?;
    let addr = listener.local_addr()?;
    let shared = Arc::new(Shared::default());
    shared.update(|s| {
        s.status = super::status(s.version, 0, "building", None, &[], None);
    });
    let server = Arc::clone(&shared);
    std::thread::Builder::new()
        .name("viewer".into())
        .spawn(move || {
            for stream in listener.incoming().flatten() {
                let shared = Arc::clone(&server);
                // A connection that cannot get a thread is dropped (the browser retries).
                let _ = std::thread::Builder::new()
                    .name("viewer-connection".into())
                    .spawn(move || {
                        let _ = handle(stream, &shared, addr);
                    });
            }
        })?;
    Ok(Viewer { shared, addr })
}

/// A request's method and path (without the query) and its query string.
#[derive(Debug, PartialEq)]
struct Request {
    method: String,
    path: String,
    query: String,
    host: Option<String>,
}

/// Reads one request and answers it.
fn handle(stream: TcpStream, shared: &Shared, addr: SocketAddr) -> io::Result<()> {
    stream.set_read_timeout(Some(READ_TIMEOUT))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut out = stream;
    let request = match read_request(&mut reader) {
        Ok(r) => r,
        Err(e) => return respond(&mut out, 400, "text/plain", e.as_bytes(), false),
    };
    if !host_allowed(request.host.as_deref(), addr.port()) {
        return respond(
            &mut out,
            403,
            "text/plain",
            b"the viewer answers only requests to 127.0.0.1 or localhost",
            false,
        );
    }
    let head_only = match request.method.as_str() {
        "GET" => false,
        "HEAD" => true,
        _ => return respond(&mut out, 405, "text/plain", b"GET only", false),
    };
    if request.path == "/events" {
        return events(&mut out, shared);
    }
    match answer(&request, shared) {
        Some((content_type, body)) => respond(&mut out, 200, content_type, body.bytes(), head_only),
        None => respond(&mut out, 404, "text/plain", b"not found", head_only),
    }
}

/// A response body: an embedded file, or published bytes shared with the state (a
/// request never copies the model).
enum Body {
    Embedded(&'static [u8]),
    Bytes(Arc<Vec<u8>>),
    Text(Arc<String>),
}

impl Body {
    fn bytes(&self) -> &[u8] {
        match self {
            Body::Embedded(b) => b,
            Body::Bytes(b) => b,
            Body::Text(t) => t.as_bytes(),
        }
    }
}

/// The body and content type of a plain path, or `None` for an unknown one.
fn answer(request: &Request, shared: &Shared) -> Option<(&'static str, Body)> {
    let json = "application/json";
    match request.path.as_str() {
        "/status.json" => Some((json, Body::Text(Arc::new(shared.lock().status.clone())))),
        "/model.glb" => {
            let s = shared.lock();
            (s.model_version > 0).then(|| ("model/gltf-binary", Body::Bytes(Arc::clone(&s.glb))))
        }
        "/info.json" => {
            let s = shared.lock();
            (s.model_version > 0).then(|| (json, Body::Text(Arc::clone(&s.info))))
        }
        "/seams.json" => seams(shared).map(|t| (json, Body::Text(t))),
        "/piece.json" => {
            let name = query_value(&request.query, "name")?;
            let parts = shared.lock().parts.clone()?;
            let info = crate::pipeline::viewer_data::piece_info(&parts, &name)?;
            Some((json, Body::Text(Arc::new(info.to_string()))))
        }
        path => assets::get(path).map(|a| (a.content_type, Body::Embedded(a.bytes))),
    }
}

/// `/seams.json` of the model served, made once per model (outside the lock: the
/// scene is shared, and a rebuild may publish meanwhile).
fn seams(shared: &Shared) -> Option<Arc<String>> {
    let (scene, version) = {
        let s = shared.lock();
        if let Some(cached) = &s.seams {
            return Some(Arc::clone(cached));
        }
        (s.scene.clone()?, s.model_version)
    };
    let text = Arc::new(crate::pipeline::viewer_data::seams_info(&scene).to_string());
    let mut s = shared.lock();
    if s.model_version == version {
        s.seams = Some(Arc::clone(&text));
    }
    Some(text)
}

/// The event stream: the status now, then after every change, until the page goes.
fn events(out: &mut TcpStream, shared: &Shared) -> io::Result<()> {
    out.write_all(
        b"HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\nConnection: keep-alive\r\n\r\n",
    )?;
    let mut seen = 0;
    loop {
        match shared.wait_status(seen, KEEPALIVE) {
            Some((version, status)) => {
                seen = version;
                out.write_all(format!("data: {status}\n\n").as_bytes())?;
            }
            None => out.write_all(b": keepalive\n\n")?,
        }
        out.flush()?;
    }
}

/// Writes a whole response and closes the exchange.
fn respond(
    out: &mut TcpStream,
    code: u16,
    content_type: &str,
    body: &[u8],
    head_only: bool,
) -> io::Result<()> {
    let reason = match code {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        _ => "Method Not Allowed",
    };
    let head = format!(
        "HTTP/1.1 {code} {reason}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        body.len()
    );
    out.write_all(head.as_bytes())?;
    if !head_only {
        out.write_all(body)?;
    }
    out.flush()
}

/// The request line and the `Host` header, or why the request is not one.
fn read_request(reader: &mut impl BufRead) -> Result<Request, String> {
    let mut line = String::new();
    let mut read = 0;
    let mut request: Option<Request> = None;
    loop {
        line.clear();
        let n = reader
            .read_line(&mut line)
            .map_err(|e| format!("cannot read the request: {e}"))?;
        read += n;
        if n == 0 || read > MAX_HEAD {
            return Err("incomplete or oversized request head".into());
        }
        let text = line.trim_end_matches(['\r', '\n']);
        match request.as_mut() {
            None => request = Some(parse_request_line(text)?),
            Some(_) if text.is_empty() => break,
            Some(r) => {
                if let Some((name, value)) = text.split_once(':') {
                    if name.trim().eq_ignore_ascii_case("host") {
                        r.host = Some(value.trim().to_string());
                    }
                }
            }
        }
    }
    request.ok_or_else(|| "no request line".into())
}

/// `GET /path?query HTTP/1.1` split into its parts.
fn parse_request_line(line: &str) -> Result<Request, String> {
    let mut parts = line.split(' ');
    let (Some(method), Some(target), Some(version)) = (parts.next(), parts.next(), parts.next())
    else {
        return Err(format!("not a request line: {line:?}"));
    };
    if !version.starts_with("HTTP/1.") {
        return Err(format!("unsupported protocol {version:?}"));
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    Ok(Request {
        method: method.to_string(),
        path: path.to_string(),
        query: query.to_string(),
        host: None,
    })
}

/// Whether a request's `Host` names this server on the loopback: `127.0.0.1:PORT` or
/// `localhost:PORT` (a request without a `Host`, from a plain tool, is let in).
fn host_allowed(host: Option<&str>, port: u16) -> bool {
    let Some(host) = host else { return true };
    let (name, given_port) = match host.rsplit_once(':') {
        Some((n, p)) => (n, p.parse::<u16>().ok()),
        None => (host, Some(80)),
    };
    let loopback = matches!(
        name.to_ascii_lowercase().as_str(),
        "127.0.0.1" | "localhost" | "[::1]"
    );
    loopback && given_port == Some(port)
}

/// The percent-decoded value of `key` in a query string (`a=1&name=binder%2Ffront`).
fn query_value(query: &str, key: &str) -> Option<String> {
    query.split('&').find_map(|pair| {
        let (k, v) = pair.split_once('=')?;
        (k == key).then(|| percent_decode(v))
    })
}

/// `%XX` escapes and `+` (a space) decoded; an invalid escape is kept as written, and
/// bytes that do not form UTF-8 are replaced.
fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => match (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                (Some(h), Some(l)) => {
                    out.push((h * 16 + l) as u8);
                    i += 3;
                    continue;
                }
                _ => out.push(b'%'),
            },
            b'+' => out.push(b' '),
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_head_gives_its_path_query_and_host() {
        let head = "GET /piece.json?name=binder%2Ffront HTTP/1.1\r\nHost: 127.0.0.1:4173\r\nAccept: */*\r\n\r\n";
        let r = read_request(&mut head.as_bytes()).expect("a valid head");
        assert_eq!(r.method, "GET");
        assert_eq!(r.path, "/piece.json");
        assert_eq!(
            query_value(&r.query, "name").as_deref(),
            Some("binder/front")
        );
        assert_eq!(r.host.as_deref(), Some("127.0.0.1:4173"));
    }

    #[test]
    fn bad_heads_are_refused() {
        assert!(read_request(&mut "GET /\r\n\r\n".as_bytes()).is_err());
        assert!(read_request(&mut "GET / SPDY/3\r\n\r\n".as_bytes()).is_err());
        assert!(read_request(&mut "GET / HTTP/1.1\r\nHost: x".as_bytes()).is_err());
        let huge = format!("GET / HTTP/1.1\r\nX: {}\r\n\r\n", "a".repeat(MAX_HEAD));
        assert!(read_request(&mut huge.as_bytes()).is_err());
    }

    #[test]
    fn only_loopback_hosts_on_our_port_are_let_in() {
        assert!(host_allowed(Some("127.0.0.1:4173"), 4173));
        assert!(host_allowed(Some("LOCALHOST:4173"), 4173));
        assert!(host_allowed(None, 4173));
        assert!(!host_allowed(Some("127.0.0.1:4174"), 4173));
        assert!(!host_allowed(Some("evil.example:4173"), 4173));
        assert!(!host_allowed(Some("localhost"), 4173));
    }

    #[test]
    fn percent_escapes_decode_and_bad_ones_stay() {
        assert_eq!(percent_decode("a%2Fb+c"), "a/b c");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz%4"), "%zz%4");
        assert_eq!(percent_decode("%C3%A9"), "é");
    }
}
