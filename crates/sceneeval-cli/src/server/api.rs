//! A page's typed JSON API: routes under `/api/`, each a handler from the page's state and a
//! request type to a response type.

use std::collections::BTreeMap;
use std::fmt;

use serde::Serialize;
use serde::de::DeserializeOwned;

/// A refusal of a request: the HTTP status and a message for the page (sent as
/// `{"error": MESSAGE}`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ApiError {
    /// The HTTP status (400, 403, 404, ...).
    pub status: u16,
    /// What is wrong, for the person using the page.
    pub message: String,
}

impl ApiError {
    /// A refusal with `status`.
    pub fn new(status: u16, message: impl Into<String>) -> Self {
        ApiError {
            status,
            message: message.into(),
        }
    }

    /// 400: the request is malformed.
    pub fn bad_request(message: impl Into<String>) -> Self {
        ApiError::new(400, message)
    }

    /// 404: what the request names does not exist.
    pub fn not_found(message: impl Into<String>) -> Self {
        ApiError::new(404, message)
    }
}

impl fmt::Display for ApiError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.status, self.message)
    }
}

impl std::error::Error for ApiError {}

/// The parameters of a GET route that takes none (any query is refused).
#[derive(Debug, Clone, Copy, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoParams {}

/// A response that is not JSON: bytes and their type (an image the page shows). The page
/// fetches it with its token (`sceneevalBlobUrl` of the client script gives a `blob:` URL an
/// `<img>` can show).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Raw {
    /// Its `Content-Type` (`image/png`).
    pub content_type: &'static str,
    /// Its bytes.
    pub bytes: Vec<u8>,
}

/// What a route answers: the type and the bytes.
pub(crate) type Reply = (&'static str, Vec<u8>);

/// The type of every JSON response.
const JSON: &str = "application/json";

/// How a route reads its request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Method {
    /// The request type from the query string, no body.
    Get,
    /// The request type from the JSON body.
    Post,
}

/// What a request brings to its route: the query string (GET) or the body (POST).
pub(crate) enum Input<'a> {
    Query(&'a str),
    Body(&'a [u8]),
}

type Handler<S> = Box<dyn Fn(&mut S, Input<'_>) -> Result<Reply, ApiError> + Send + Sync>;

/// The routes of a page under `/api/`: `Api::new().get("candidates", list).post("save", save)`.
pub struct Api<S> {
    routes: BTreeMap<(Method, String), Handler<S>>,
}

impl<S> fmt::Debug for Api<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.routes.keys()).finish()
    }
}

impl<S> Default for Api<S> {
    fn default() -> Self {
        Api {
            routes: BTreeMap::new(),
        }
    }
}

impl<S> Api<S> {
    /// No routes.
    pub fn new() -> Self {
        Api::default()
    }

    /// `GET /api/NAME?...`: `handler` gets the query's parameters as `Q` (each parameter a
    /// string field; [`NoParams`] for none) and its `R` is sent as JSON.
    pub fn get<Q, R, F>(mut self, name: &str, handler: F) -> Self
    where
        S: 'static,
        Q: DeserializeOwned + 'static,
        R: Serialize + 'static,
        F: Fn(&mut S, Q) -> Result<R, ApiError> + Send + Sync + 'static,
    {
        let call = move |state: &mut S, input: Input<'_>| {
            let Input::Query(query) = input else {
                return Err(ApiError::bad_request("a GET has no body"));
            };
            reply(handler(state, query_params(query)?)?)
        };
        self.routes.insert((Method::Get, name.to_owned()), Box::new(call));
        self
    }

    /// `GET /api/NAME?...` answered with bytes of their own type ([`Raw`]: an image), the
    /// query read as for [`Api::get`].
    pub fn get_raw<Q, F>(mut self, name: &str, handler: F) -> Self
    where
        S: 'static,
        Q: DeserializeOwned + 'static,
        F: Fn(&mut S, Q) -> Result<Raw, ApiError> + Send + Sync + 'static,
    {
        let call = move |state: &mut S, input: Input<'_>| {
            let Input::Query(query) = input else {
                return Err(ApiError::bad_request("a GET has no body"));
            };
            let raw = handler(state, query_params(query)?)?;
            Ok((raw.content_type, raw.bytes))
        };
        self.routes.insert((Method::Get, name.to_owned()), Box::new(call));
        self
    }

    /// `POST /api/NAME` with a JSON body: `handler` gets the body as `B` (a body that is not a
    /// `B` is refused, 400) and its `R` is sent as JSON.
    pub fn post<B, R, F>(mut self, name: &str, handler: F) -> Self
    where
        S: 'static,
        B: DeserializeOwned + 'static,
        R: Serialize + 'static,
        F: Fn(&mut S, B) -> Result<R, ApiError> + Send + Sync + 'static,
    {
        let route = name.to_owned();
        let call = move |state: &mut S, input: Input<'_>| {
            let Input::Body(body) = input else {
                return Err(ApiError::bad_request("a POST needs a JSON body"));
            };
            let request = serde_json::from_slice(body).map_err(|e| {
                ApiError::bad_request(format!("the body is not a request of /api/{route}: {e}"))
            })?;
            reply(handler(state, request)?)
        };
        self.routes
            .insert((Method::Post, name.to_owned()), Box::new(call));
        self
    }

    /// Whether `name` has a route for some method (a wrong method is then 405, not 404).
    pub(crate) fn knows(&self, name: &str) -> bool {
        self.routes.keys().any(|(_, n)| n == name)
    }

    /// Calls the route of `method` and `name`: the response's type and bytes, or the refusal.
    pub(crate) fn call(
        &self,
        state: &mut S,
        method: Method,
        name: &str,
        input: Input<'_>,
    ) -> Result<Reply, ApiError> {
        match self.routes.get(&(method, name.to_owned())) {
            Some(handler) => handler(state, input),
            None if self.knows(name) => Err(ApiError::new(
                405,
                format!("this method is not allowed on /api/{name}"),
            )),
            None => Err(ApiError::not_found(format!("no API endpoint /api/{name}"))),
        }
    }
}

/// The response as JSON.
fn reply(value: impl Serialize) -> Result<Reply, ApiError> {
    let bytes = serde_json::to_vec(&value)
        .map_err(|e| ApiError::new(500, format!("cannot write the response as JSON: {e}")))?;
    Ok((JSON, bytes))
}

/// The query's parameters (`a=1&b=x%20y`, `+` a space, percent-decoded) as `Q`, each a string.
fn query_params<Q: DeserializeOwned>(query: &str) -> Result<Q, ApiError> {
    let mut map = serde_json::Map::new();
    for pair in query.split('&').filter(|p| !p.is_empty()) {
        let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
        let decode = |s: &str| {
            urlencoding::decode(&s.replace('+', " "))
                .map(|v| v.into_owned())
                .map_err(|e| ApiError::bad_request(format!("the query is not UTF-8: {e}")))
        };
        map.insert(decode(key)?, serde_json::Value::String(decode(value)?));
    }
    serde_json::from_value(serde_json::Value::Object(map))
        .map_err(|e| ApiError::bad_request(format!("the query does not fit this request: {e}")))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use serde::Deserialize;

    use super::*;

    #[derive(Debug, Deserialize)]
    struct Id {
        id: String,
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Add {
        n: i64,
    }

    fn api() -> Api<i64> {
        Api::new()
            .get("value", |s: &mut i64, _: NoParams| Ok(*s))
            .get("echo", |_: &mut i64, q: Id| Ok(q.id))
            .post("add", |s: &mut i64, b: Add| {
                *s += b.n;
                Ok(serde_json::json!({ "value": *s }))
            })
            .get_raw("picture", |s: &mut i64, _: NoParams| {
                Ok(Raw {
                    content_type: "image/png",
                    bytes: s.to_le_bytes().to_vec(),
                })
            })
    }

    #[test]
    fn typed_routes_read_their_request_and_write_json() {
        let api = api();
        let mut state = 1;
        let text = |r: Result<Reply, ApiError>| {
            let (kind, bytes) = r.unwrap();
            assert_eq!(kind, "application/json");
            String::from_utf8(bytes).unwrap()
        };
        assert_eq!(
            text(api.call(&mut state, Method::Get, "value", Input::Query(""))),
            "1"
        );
        assert_eq!(
            text(api.call(&mut state, Method::Get, "echo", Input::Query("id=a+b%2Fc&x"))),
            "\"a b/c\""
        );
        assert_eq!(
            text(api.call(&mut state, Method::Post, "add", Input::Body(br#"{"n": 41}"#))),
            r#"{"value":42}"#
        );
        assert_eq!(state, 42);
        // A route of bytes: their own type, not JSON.
        assert_eq!(
            api.call(&mut state, Method::Get, "picture", Input::Query(""))
                .unwrap(),
            ("image/png", 42i64.to_le_bytes().to_vec())
        );
    }

    #[test]
    fn requests_that_do_not_fit_are_refused_with_a_status() {
        let api = api();
        let mut state = 0;
        let status = |m, name, input| api.call(&mut 0, m, name, input).unwrap_err();
        assert_eq!(status(Method::Get, "nope", Input::Query("")).status, 404);
        assert_eq!(status(Method::Post, "value", Input::Body(b"{}")).status, 405);
        let e = status(Method::Get, "echo", Input::Query(""));
        assert_eq!(e.status, 400);
        assert!(e.message.contains("missing field `id`"), "{e}");
        assert_eq!(status(Method::Get, "value", Input::Query("x=1")).status, 400);
        let e = status(Method::Post, "add", Input::Body(b"{\"n\": "));
        assert!(
            e.message.starts_with("the body is not a request of /api/add"),
            "{e}"
        );
        assert_eq!(
            status(Method::Post, "add", Input::Body(br#"{"n": 1, "m": 2}"#)).status,
            400
        );
        assert_eq!(status(Method::Get, "echo", Input::Query("id=%FF")).status, 400);
        // Nothing changed the state.
        assert_eq!(
            api.call(&mut state, Method::Get, "value", Input::Query(""))
                .unwrap(),
            ("application/json", b"0".to_vec())
        );
    }
}
