//! JSON-RPC over a byte stream (`Content-Length` framing, LSP base protocol), driving a
//! tower-lsp-server [`LspService`].
//!
//! tower-lsp-server's own `Server` stops reading after the first message it cannot decode and
//! runs at most four messages at a time (so an edit can queue behind four slow requests
//! instead of cancelling them). This loop keeps the service and fixes both:
//!
//! * a frame that is not JSON gets a `ParseError` response (id `null`), one that is JSON but
//!   not a JSON-RPC message an `InvalidRequest` response, and reading carries on;
//! * every message is handed to the service as soon as it arrives and polled once right away,
//!   so notifications take effect in the order they were sent; what is still pending then
//!   runs as a task of its own;
//! * every request gets exactly one answer: a panic in a handler becomes an `InternalError`
//!   response and a `window/logMessage`, and a `$/` request the server does not know gets
//!   `MethodNotFound` (tower-lsp-server drops it).

use std::future::Future;
use std::panic::AssertUnwindSafe;
use std::pin::Pin;
use std::task::{Context, Poll};

use futures::{SinkExt, StreamExt};
use serde_json::Value;
use tokio::io::{
    AsyncBufRead, AsyncBufReadExt, AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, BufReader,
};
use tokio::sync::mpsc;
use tower_lsp_server::jsonrpc::{Error, ErrorCode, Id, Request, Response};
use tower_lsp_server::ls_types::MessageType;
use tower_lsp_server::{Client, ClientSocket, LanguageServer, LspService};
use tower_service::Service;

/// The largest message body accepted (larger ones are skipped with a `ParseError`).
const MAX_BODY: usize = 256 * 1024 * 1024;

/// How the conversation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ending {
    /// The client sent `exit`.
    Exit,
    /// The input ended (or failed) without `exit`.
    InputClosed,
}

/// Serves `service` on `input`/`output` until `exit` or the end of the input. `client` is the
/// service's client handle (for log messages about panics).
pub(crate) async fn serve<S, I, O>(
    input: I,
    output: O,
    mut service: LspService<S>,
    socket: ClientSocket,
    client: Client,
) -> Ending
where
    S: LanguageServer,
    I: AsyncRead + Unpin,
    O: AsyncWrite + Unpin + Send + 'static,
{
    let (outgoing, outbox) = mpsc::unbounded_channel::<Outgoing>();
    let writer = tokio::spawn(write_messages(output, outbox));

    let (mut server_requests, mut client_responses) = socket.split();
    let forward = {
        let outgoing = outgoing.clone();
        tokio::spawn(async move {
            while let Some(request) = server_requests.next().await {
                if let Ok(body) = serde_json::to_string(&request) {
                    let _ = outgoing.send(Outgoing::Message(body));
                }
            }
        })
    };

    let mut reader = BufReader::new(input);
    let ending = loop {
        let body = match read_frame(&mut reader).await {
            Frame::Body(body) => body,
            Frame::Malformed(reason) => {
                respond(
                    &outgoing,
                    &Response::from_error(Id::Null, error(ErrorCode::ParseError, reason)),
                );
                continue;
            }
            Frame::End => break Ending::InputClosed,
        };
        let message = match Incoming::decode(&body) {
            Ok(message) => message,
            Err((id, error)) => {
                respond(&outgoing, &Response::from_error(id, error));
                continue;
            }
        };
        match message {
            Incoming::Response(response) => {
                // Answers to the server's own requests (progress, registrations).
                if client_responses.send(response).await.is_err() {
                    break Ending::InputClosed;
                }
            }
            Incoming::Request(request) => {
                let is_exit = request.method() == "exit";
                if !ready(&mut service).await {
                    // The service has exited.
                    break Ending::Exit;
                }
                dispatch(&mut service, request, &outgoing, &client).await;
                if is_exit {
                    break Ending::Exit;
                }
            }
        }
    };

    forward.abort();
    let (done, flushed) = tokio::sync::oneshot::channel();
    let _ = outgoing.send(Outgoing::Flush(done));
    let _ = flushed.await;
    writer.abort();
    ending
}

/// Waits until the service takes messages; `false` once it has exited.
async fn ready<S: LanguageServer>(service: &mut LspService<S>) -> bool {
    loop {
        match std::future::poll_fn(|cx| Poll::Ready(service.poll_ready(cx))).await {
            Poll::Ready(ready) => return ready.is_ok(),
            // The service registers no waker while it is busy initializing: look again soon.
            Poll::Pending => tokio::time::sleep(std::time::Duration::from_millis(5)).await,
        }
    }
}

/// Hands one request or notification to the service and polls it once, so its synchronous
/// part (for a notification: queuing the change) runs before the next message is read.
async fn dispatch<S: LanguageServer>(
    service: &mut LspService<S>,
    request: Request,
    outgoing: &mpsc::UnboundedSender<Outgoing>,
    client: &Client,
) {
    let id = request.id().cloned();
    let method = request.method().to_owned();
    let call = match std::panic::catch_unwind(AssertUnwindSafe(|| service.call(request))) {
        Ok(call) => call,
        Err(payload) => {
            let message = super::panic_message(payload.as_ref());
            report_panic(outgoing, client, id, &method, message).await;
            return;
        }
    };
    let mut answer = Box::pin(CatchUnwind(call));
    let polled = std::future::poll_fn(|cx| Poll::Ready(answer.as_mut().poll(cx))).await;
    match polled {
        Poll::Ready(outcome) => finish(outcome, outgoing, client, id, &method).await,
        Poll::Pending => {
            let outgoing = outgoing.clone();
            let client = client.clone();
            tokio::spawn(async move {
                let outcome = answer.await;
                finish(outcome, &outgoing, &client, id, &method).await;
            });
        }
    }
}

/// What a service call ended with: its response, or the panic that ended it.
type Outcome<E> = Result<Result<Option<Response>, E>, Box<dyn std::any::Any + Send>>;

/// Sends the answer to a request, making sure every request (a message with an id) gets one.
async fn finish<E>(
    outcome: Outcome<E>,
    outgoing: &mpsc::UnboundedSender<Outgoing>,
    client: &Client,
    id: Option<Id>,
    method: &str,
) {
    match outcome {
        Ok(Ok(Some(response))) => respond(outgoing, &response),
        Ok(Ok(None)) | Ok(Err(_)) => {
            if let Some(id) = id {
                // tower-lsp-server drops unknown `$/` requests; LSP wants MethodNotFound.
                let code = if method.starts_with("$/") {
                    ErrorCode::MethodNotFound
                } else {
                    ErrorCode::InvalidRequest
                };
                respond(
                    outgoing,
                    &Response::from_error(id, error(code, format!("{method}: no answer"))),
                );
            }
        }
        Err(payload) => {
            let message = super::panic_message(payload.as_ref());
            report_panic(outgoing, client, id, method, message).await;
        }
    }
}

/// Answers a request whose handler panicked with `InternalError` and logs the panic.
async fn report_panic(
    outgoing: &mpsc::UnboundedSender<Outgoing>,
    client: &Client,
    id: Option<Id>,
    method: &str,
    panic_message: String,
) {
    let message = format!("internal error in {method}: {panic_message}");
    if let Some(id) = id {
        respond(
            outgoing,
            &Response::from_error(id, error(ErrorCode::InternalError, message.clone())),
        );
    }
    client.log_message(MessageType::ERROR, message).await;
}

fn error(code: ErrorCode, message: impl Into<String>) -> Error {
    Error {
        code,
        message: message.into().into(),
        data: None,
    }
}

fn respond(outgoing: &mpsc::UnboundedSender<Outgoing>, response: &Response) {
    if let Ok(body) = serde_json::to_string(response) {
        let _ = outgoing.send(Outgoing::Message(body));
    }
}

/// A future that turns a panic while polling into an `Err` with the panic's payload.
struct CatchUnwind<F>(F);

impl<F: Future + Unpin> Future for CatchUnwind<F> {
    type Output = Result<F::Output, Box<dyn std::any::Any + Send>>;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let inner = &mut self.0;
        match std::panic::catch_unwind(AssertUnwindSafe(|| Pin::new(inner).poll(cx))) {
            Ok(Poll::Pending) => Poll::Pending,
            Ok(Poll::Ready(output)) => Poll::Ready(Ok(output)),
            Err(payload) => Poll::Ready(Err(payload)),
        }
    }
}

/// A decoded message from the client.
enum Incoming {
    Request(Request),
    Response(Response),
}

impl Incoming {
    /// Decodes a message body; on failure, the id to answer (if one can be read) and the
    /// error.
    fn decode(body: &[u8]) -> Result<Incoming, (Id, Error)> {
        let value: Value = serde_json::from_slice(body).map_err(|e| {
            (
                Id::Null,
                error(ErrorCode::ParseError, format!("not JSON: {e}")),
            )
        })?;
        let id = value
            .get("id")
            .and_then(|id| serde_json::from_value::<Id>(id.clone()).ok())
            .unwrap_or(Id::Null);
        let invalid = |reason: String| (id.clone(), error(ErrorCode::InvalidRequest, reason));
        if !value.is_object() {
            return Err(invalid("a message is a JSON object".into()));
        }
        if value.get("method").is_some() {
            serde_json::from_value::<Request>(value)
                .map(Incoming::Request)
                .map_err(|e| invalid(format!("not a JSON-RPC request: {e}")))
        } else if value.get("result").is_some() || value.get("error").is_some() {
            serde_json::from_value::<Response>(value)
                .map(Incoming::Response)
                .map_err(|e| invalid(format!("not a JSON-RPC response: {e}")))
        } else {
            Err(invalid(
                "a message has a method, a result or an error".into(),
            ))
        }
    }
}

/// Something for the writer.
enum Outgoing {
    /// A message body to frame and write.
    Message(String),
    /// Flush and report back: everything queued before has been written.
    Flush(tokio::sync::oneshot::Sender<()>),
}

async fn write_messages<O: AsyncWrite + Unpin>(
    mut output: O,
    mut outbox: mpsc::UnboundedReceiver<Outgoing>,
) {
    while let Some(item) = outbox.recv().await {
        match item {
            Outgoing::Message(body) => {
                // One write for header and body: each write to tokio's stdout is a round trip
                // to a blocking thread, and the body waits for the header's.
                let mut frame = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
                frame.extend_from_slice(body.as_bytes());
                let written = async {
                    output.write_all(&frame).await?;
                    output.flush().await
                }
                .await;
                if written.is_err() {
                    // The client is gone; nothing more can be said.
                    return;
                }
            }
            Outgoing::Flush(done) => {
                let _ = output.flush().await;
                let _ = done.send(());
            }
        }
    }
}

/// One frame of the input.
#[derive(Debug, PartialEq, Eq)]
enum Frame {
    Body(Vec<u8>),
    /// A header without a usable `Content-Length`, or a body too large; the reason.
    Malformed(String),
    /// The input ended.
    End,
}

/// Reads one frame: header lines up to an empty line, then `Content-Length` bytes. Header
/// lines may end in CR LF or LF; unknown headers are ignored.
async fn read_frame<R: AsyncBufRead + Unpin>(reader: &mut R) -> Frame {
    let mut content_length: Option<Result<usize, String>> = None;
    let mut saw_header = false;
    let mut line = Vec::new();
    loop {
        line.clear();
        match reader.read_until(b'\n', &mut line).await {
            Ok(0) | Err(_) => return Frame::End,
            Ok(_) => {}
        }
        let text = String::from_utf8_lossy(&line);
        let text = text.trim_end_matches(['\r', '\n']);
        if text.is_empty() {
            if saw_header {
                break;
            }
            // Blank lines between messages.
            continue;
        }
        saw_header = true;
        if let Some((name, value)) = text.split_once(':')
            && name.trim().eq_ignore_ascii_case("content-length")
        {
            content_length = Some(
                value
                    .trim()
                    .parse::<usize>()
                    .map_err(|_| format!("bad Content-Length '{}'", value.trim())),
            );
        }
    }
    let length = match content_length {
        Some(Ok(length)) => length,
        Some(Err(reason)) => return Frame::Malformed(reason),
        None => return Frame::Malformed("a message header without Content-Length".into()),
    };
    if length > MAX_BODY {
        let mut rest = reader.take(length as u64);
        let _ = tokio::io::copy(&mut rest, &mut tokio::io::sink()).await;
        return Frame::Malformed(format!("a message of {length} bytes is too large"));
    }
    let mut body = vec![0; length];
    match reader.read_exact(&mut body).await {
        Ok(_) => Frame::Body(body),
        Err(_) => Frame::End,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    async fn frames(input: &[u8]) -> Vec<Frame> {
        let mut reader = BufReader::new(input);
        let mut frames = Vec::new();
        loop {
            let frame = read_frame(&mut reader).await;
            if frame == Frame::End {
                return frames;
            }
            frames.push(frame);
        }
    }

    #[tokio::test]
    async fn frames_are_read_and_garbage_is_reported() {
        let input = b"Content-Length: 2\r\n\r\n{}garbage\r\n\r\nContent-Length: x\r\n\r\nContent-Type: a\ncontent-length: 3\n\n[1]";
        assert_eq!(
            frames(input).await,
            vec![
                Frame::Body(b"{}".to_vec()),
                Frame::Malformed("a message header without Content-Length".into()),
                Frame::Malformed("bad Content-Length 'x'".into()),
                Frame::Body(b"[1]".to_vec()),
            ]
        );
    }

    #[tokio::test]
    async fn a_panic_while_polling_becomes_an_error() {
        let panicking = Box::pin(async { panic!("boom") });
        let outcome: Result<(), _> = CatchUnwind(panicking).await;
        let payload = outcome.expect_err("the panic is caught");
        assert_eq!(super::super::panic_message(payload.as_ref()), "boom");
        let fine = CatchUnwind(Box::pin(async { 7 })).await;
        assert_eq!(fine.ok(), Some(7));
    }

    #[test]
    fn bodies_decode_to_requests_responses_or_errors() {
        let request = br#"{"jsonrpc":"2.0","id":1,"method":"shutdown"}"#;
        assert!(matches!(
            Incoming::decode(request),
            Ok(Incoming::Request(_))
        ));
        let response = br#"{"jsonrpc":"2.0","id":1,"result":null}"#;
        assert!(matches!(
            Incoming::decode(response),
            Ok(Incoming::Response(_))
        ));
        let Err((id, parse)) = Incoming::decode(b"{oops") else {
            panic!("garbage decoded");
        };
        assert_eq!((id, parse.code), (Id::Null, ErrorCode::ParseError));
        let Err((id, invalid)) = Incoming::decode(br#"{"jsonrpc":"1.0","id":7,"method":"x"}"#)
        else {
            panic!("a wrong version decoded");
        };
        assert_eq!(
            (id, invalid.code),
            (Id::Number(7), ErrorCode::InvalidRequest)
        );
        let Err((_, invalid)) = Incoming::decode(b"[]") else {
            panic!("a batch decoded");
        };
        assert_eq!(invalid.code, ErrorCode::InvalidRequest);
    }
}
