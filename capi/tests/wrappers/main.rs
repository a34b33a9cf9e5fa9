//! The C functions of the commands (`capi/src/commands.rs`) are generated from one list
//! (`list.rs` here): a command is one entry for both transports. cbindgen reads the generated
//! file like any other source (it does not expand macros, hence a generator and not a macro).
//! This test fails when the checked-in file differs from what the list generates now; to
//! write it anew: `MCM_UPDATE_CAPI=1 cargo test -p mcm-capi --test wrappers` (then
//! `MCM_UPDATE_HEADER=1 cargo test -p mcm-capi --test header` for the header); that run writes
//! and says what changed instead of comparing (refused when `CI` is set: CI always compares).

#[path = "../common/mod.rs"]
mod common;
mod list;

use std::fmt::Write;

/// The transports a command exists on.
#[derive(Clone, Copy, PartialEq)]
pub enum On {
    Both,
    Tcp,
    Shm,
}

/// What a command answers, besides success.
#[derive(Clone, Copy)]
pub enum Answer {
    /// Nothing.
    Ack,
    /// The state after a mode change over TCP (an optional `status`); nothing over shared
    /// memory.
    Mode,
    /// A required output `name` of C type `ty`, written with `conv` from the answer `a`.
    Out(&'static str, &'static str, &'static str),
    /// As `Out`, with the type per transport (TCP, shared memory).
    OutPer(&'static str, &'static str, &'static str, &'static str),
    /// An optional output (may be NULL).
    Put(&'static str, &'static str, &'static str),
}

impl Answer {
    /// The answer on one transport: an `OutPer` is the `Out` of that transport's type.
    fn on(self, tcp: bool) -> Answer {
        match self {
            Answer::OutPer(name, tcp_ty, shm_ty, conv) => {
                Answer::Out(name, if tcp { tcp_ty } else { shm_ty }, conv)
            }
            other => other,
        }
    }
}

/// One command of the list.
pub struct Command {
    name: &'static str,
    on: On,
    doc: &'static str,
    tcp_doc: &'static str,
    shm_doc: &'static str,
    params: Vec<(&'static str, &'static str)>,
    answer: Answer,
    /// The client's call, over TCP and over shared memory.
    call: (&'static str, &'static str),
    fallible: bool,
}

fn command(on: On, name: &'static str, doc: &'static str) -> Command {
    Command {
        name,
        on,
        doc,
        tcp_doc: "",
        shm_doc: "",
        params: Vec::new(),
        answer: Answer::Ack,
        call: ("", ""),
        fallible: true,
    }
}

/// A command of both transports.
pub fn both(name: &'static str, doc: &'static str) -> Command {
    command(On::Both, name, doc)
}

/// A command of the TCP client only.
pub fn tcp(name: &'static str, doc: &'static str) -> Command {
    command(On::Tcp, name, doc)
}

/// A command of the shared-memory client only.
pub fn shm(name: &'static str, doc: &'static str) -> Command {
    command(On::Shm, name, doc)
}

impl Command {
    pub fn param(mut self, name: &'static str, ty: &'static str) -> Self {
        self.params.push((name, ty));
        self
    }
    pub fn answer(mut self, a: Answer) -> Self {
        self.answer = a;
        self
    }
    pub fn tcp_doc(mut self, doc: &'static str) -> Self {
        self.tcp_doc = doc;
        self
    }
    pub fn shm_doc(mut self, doc: &'static str) -> Self {
        self.shm_doc = doc;
        self
    }
    /// The same call on both clients.
    pub fn call(mut self, call: &'static str) -> Self {
        self.call = (call, call);
        self
    }
    /// The call on the TCP client and on the shared-memory client.
    pub fn call_per(mut self, tcp: &'static str, shm: &'static str) -> Self {
        self.call = (tcp, shm);
        self
    }
    /// The client's method returns its answer, not a `Result`.
    pub fn infallible(mut self) -> Self {
        self.fallible = false;
        self
    }
}

/// `text` as `///` lines of at most 96 characters, indented by nothing.
fn doc_lines(text: &str) -> String {
    let mut out = String::new();
    let mut line = String::from("///");
    for word in text.split_whitespace() {
        if line.len() + 1 + word.len() > 96 && line != "///" {
            out.push_str(&line);
            out.push('\n');
            line = String::from("///");
        }
        line.push(' ');
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
    out
}

fn render_one(out: &mut String, c: &Command, tcp: bool) {
    let t = if tcp { "tcp" } else { "shm" };
    let extra = if tcp { c.tcp_doc } else { c.shm_doc };
    let mut doc = if extra.is_empty() {
        c.doc.to_string()
    } else {
        format!("{} {extra}", c.doc)
    };
    let mut params: Vec<String> = vec![format!("client: *mut mcm_{t}_client_t")];
    params.extend(c.params.iter().map(|(n, ty)| format!("{n}: {ty}")));
    let mut before = String::new();
    let mut after = String::new();
    let answered = match c.answer.on(tcp) {
        Answer::Ack => false,
        Answer::Mode if !tcp => false,
        Answer::Mode => {
            doc.push_str(" `status` (may be NULL): the state after it.");
            params.push("status: *mut mcm_status_t".into());
            after = "            put(status, (&a).into());\n".into();
            true
        }
        Answer::OutPer(..) => unreachable!("`Answer::on` gives an `Out`"),
        Answer::Out(name, ty, conv) => {
            params.push(format!("{name}: *mut {ty}"));
            before = format!("            let o = convert::out({name}, F, \"{name}\")?;\n");
            after = format!("            *o = {conv};\n");
            true
        }
        Answer::Put(name, ty, conv) => {
            params.push(format!("{name}: *mut {ty}"));
            after = format!("            put({name}, {conv});\n");
            true
        }
    };
    let call = if tcp { c.call.0 } else { c.call.1 };
    let q = if c.fallible { "?" } else { "" };
    let call = if answered {
        format!("            let a = h.client.{call}{q};\n")
    } else {
        format!("            h.client.{call}{q};\n")
    };
    out.push('\n');
    out.push_str(&doc_lines(&doc));
    let _ = write!(
        out,
        "#[unsafe(no_mangle)]
pub unsafe extern \"C\" fn mcm_{t}_{name}({params}) -> mcm_error_t {{
    const F: &str = \"mcm_{t}_{name}\";
    // SAFETY: the header's contract.
    unsafe {{
        call(F, client, |h| {{
{before}{call}{after}            Ok(())
        }})
    }}
}}
",
        name = c.name,
        params = params.join(", "),
    );
}

/// The generated source of `capi/src/commands.rs`.
fn render() -> String {
    let mut out = String::from(
        "//! GENERATED from the list `capi/tests/wrappers/list.rs`; do not edit by hand:
//! `MCM_UPDATE_CAPI=1 cargo test -p mcm-capi --test wrappers` writes it anew.
//!
//! The C functions of the commands, `mcm_tcp_<name>` and `mcm_shm_<name>`: each checks its
//! arguments, calls the client (`TcpClient`, `ShmClient`) and writes its answer, under
//! `call` (a NULL handle refused, no panic across the ABI, a failure recorded in the
//! handle). Not real-time code, except where a function says so.

use crate::convert::{self, put, six, text};
use crate::error::{call, mcm_error_t};
use crate::shm::mcm_shm_client_t;
use crate::tcp::mcm_tcp_client_t;
use crate::types::*;
use mcm_client::mcm_shared::command::{MoveAll, MoveAxis};
use std::ffi::c_char;
",
    );
    let commands = list::commands();
    for tcp in [true, false] {
        for c in &commands {
            let on = if tcp { On::Tcp } else { On::Shm };
            if c.on == On::Both || c.on == on {
                render_one(&mut out, c, tcp);
            }
        }
    }
    out
}

#[test]
fn the_checked_in_wrappers_are_what_the_list_generates() {
    common::check_generated(
        "capi/src/commands.rs",
        "capi/tests/wrappers/list.rs",
        &render(),
        "MCM_UPDATE_CAPI",
        "cargo test -p mcm-capi --test wrappers",
    );
}

#[test]
fn every_command_has_a_call_and_a_name_once_per_transport() {
    let commands = list::commands();
    for c in &commands {
        assert!(
            !c.call.0.is_empty() && !c.call.1.is_empty(),
            "{}: no call",
            c.name
        );
        let twice = commands.iter().filter(|d| d.name == c.name).count();
        assert_eq!(twice, 1, "{} is listed {twice} times", c.name);
    }
}
