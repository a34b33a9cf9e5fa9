//! The HMI's line editor: builds one line from [`Input`]s, echoes it when the server echoes
//! (telnet character mode), and hands back complete lines. Runs in the gateway's async tasks,
//! not in the real-time cycle.
//!
//! Keys (with server echo): printable characters (UTF-8 too) insert; Backspace (0x08, 0x7F,
//! `IAC EC`) and Delete erase; Left/Right, Home/End, Ctrl-A/E/B/F move; Up/Down, Ctrl-P/N walk
//! the history; Tab completes the first word (and the word after `help`); Ctrl-U (or
//! `IAC EL`) erases the line, Ctrl-K to its end, Ctrl-W the word before the cursor; Ctrl-L
//! clears the screen; Ctrl-C (0x03, `IAC IP`) drops the line ([`Action::Interrupt`]);
//! Ctrl-D on an empty line ends the session ([`Action::Eof`]).
//!
//! Without server echo (`nc`, or telnet in line mode) the client edits the line itself, so
//! only characters, Backspace, Enter, Ctrl-C and Ctrl-D count. An escape sequence (an arrow or
//! function key, Alt-x, a title string) cannot be edited then, and dropping it would change the
//! line behind the person's back (`move_axis 1 3<Left>0` would move to 3, not 30): Enter after
//! a line that held one yields [`Action::Escaped`], and the line is dropped.
//!
//! Keys come through the session's one key decoder ([`super::keys`]): escape sequences are read
//! to their end whatever their length, and none of their bytes reaches the line; only the
//! editing keys above act, every other sequence is dropped whole.
//!
//! Memory is bounded: a line holds at most `max_bytes` (the rest of a longer line is dropped
//! and Enter then yields [`Action::TooLong`]); the history keeps at most [`HISTORY_LINES`]
//! lines and [`HISTORY_BYTES`] bytes.

use super::keys::{Csi, Decoded, Key, KeyDecoder};
use super::telnet::Input;
use std::collections::VecDeque;
use std::fmt::Write as _;

/// Most lines kept in the history.
pub const HISTORY_LINES: usize = 100;
/// Most bytes kept in the history.
pub const HISTORY_BYTES: usize = 256 * 1024;

/// What a key did, when it is more than an edit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Enter: the finished line (without its line end).
    Line(String),
    /// Ctrl-C: the line was dropped.
    Interrupt,
    /// Ctrl-D on an empty line.
    Eof,
    /// Enter after a line that exceeded the limit; the line was dropped.
    TooLong { limit: usize },
    /// Enter, without server echo, after a line that held an escape sequence; the line was
    /// dropped (what the person's terminal showed is not what came).
    Escaped,
}

/// One connection's line editor.
#[derive(Debug, Clone)]
pub struct Editor {
    line: Vec<char>,
    bytes: usize,
    cursor: usize,
    max_bytes: usize,
    overflow: bool,
    utf8: Vec<u8>,
    keys: KeyDecoder,
    /// An escape sequence was dropped from the line, or a key came without echo.
    escaped: bool,
    prompt: String,
    history: VecDeque<String>,
    history_bytes: usize,
    /// Position while walking the history, and the line that was being typed.
    browsing: Option<(usize, Vec<char>)>,
    words: Vec<&'static str>,
}

impl Editor {
    /// An editor for lines of at most `max_bytes`; Tab completes from `words`.
    pub fn new(max_bytes: usize, words: Vec<&'static str>) -> Self {
        Self {
            line: Vec::new(),
            bytes: 0,
            cursor: 0,
            max_bytes,
            overflow: false,
            utf8: Vec::new(),
            keys: KeyDecoder::default(),
            escaped: false,
            prompt: String::new(),
            history: VecDeque::new(),
            history_bytes: 0,
            browsing: None,
            words,
        }
    }

    /// The prompt that [`Editor::redraw`] puts before the line.
    pub fn set_prompt(&mut self, prompt: &str) {
        self.prompt.clear();
        self.prompt.push_str(prompt);
    }

    /// The line typed so far.
    pub fn text(&self) -> String {
        self.line.iter().collect()
    }

    /// Redraw the prompt and the line on the current terminal row, cursor in place.
    pub fn redraw(&self, out: &mut Vec<u8>) {
        let text = self.text();
        let mut s = format!("\r{}{}\x1b[K", self.prompt, super::render::ascii(&text));
        let back = self.line.len() - self.cursor;
        if back > 0 {
            let _ = write!(s, "\x1b[{back}D");
        }
        out.extend_from_slice(s.as_bytes());
    }

    /// Process one input; with `echo`, what the terminal must show is appended to `out`.
    pub fn feed(&mut self, input: Input, echo: bool, out: &mut Vec<u8>) -> Option<Action> {
        let b = match input {
            Input::Byte(b) => b,
            Input::Enter => return Some(self.enter(echo, out)),
            Input::Interrupt => return Some(self.interrupt(echo, out)),
            Input::EraseChar => {
                self.backspace(echo, out);
                return None;
            }
            Input::EraseLine => {
                self.kill(0, self.line.len(), echo, out);
                // Nothing of the line is left, dropped sequences neither.
                self.escaped = false;
                return None;
            }
            Input::EndOfFile => return self.ctrl_d(echo, out),
        };
        let Decoded { dropped, key } = self.keys.byte(b);
        self.escaped |= dropped;
        if self.keys.in_sequence() {
            // A character cut short by an escape sequence is dropped.
            self.utf8.clear();
        }
        match key? {
            Key::Typed(b) => self.typed(b, echo, out),
            Key::Csi(k) => {
                if echo {
                    self.key(k, out);
                } else {
                    self.escaped = true;
                }
                None
            }
        }
    }

    /// A byte that is no part of an escape sequence.
    fn typed(&mut self, b: u8, echo: bool, out: &mut Vec<u8>) -> Option<Action> {
        if b >= 0x80 {
            self.utf8_byte(b, echo, out);
            return None;
        }
        self.utf8.clear();
        match b {
            0x03 => return Some(self.interrupt(echo, out)),
            0x04 => return self.ctrl_d(echo, out),
            0x08 | 0x7F => self.backspace(echo, out),
            b'\t' if echo => self.complete(out),
            b'\t' => self.insert(' ', echo, out),
            0x20..=0x7E => self.insert(char::from(b), echo, out),
            _ if !echo => {}
            0x01 => self.move_to(0, out),
            0x05 => self.move_to(self.line.len(), out),
            0x02 => self.move_to(self.cursor.saturating_sub(1), out),
            0x06 => self.move_to((self.cursor + 1).min(self.line.len()), out),
            0x0B => self.kill(self.cursor, self.line.len(), echo, out),
            0x0C => {
                out.extend_from_slice(b"\x1b[H\x1b[2J");
                self.redraw(out);
            }
            0x0E => self.history_step(false, out),
            0x10 => self.history_step(true, out),
            0x15 => self.kill(0, self.line.len(), echo, out),
            0x17 => {
                let mut start = self.cursor;
                while start > 0 && self.line[start - 1] == ' ' {
                    start -= 1;
                }
                while start > 0 && self.line[start - 1] != ' ' {
                    start -= 1;
                }
                self.kill(start, self.cursor, echo, out);
            }
            _ => {}
        }
        None
    }

    fn enter(&mut self, echo: bool, out: &mut Vec<u8>) -> Action {
        if echo {
            out.extend_from_slice(b"\r\n");
        }
        let text = self.text();
        let overflow = std::mem::replace(&mut self.overflow, false);
        let escaped = self.escaped || self.keys.in_sequence();
        self.clear();
        if overflow {
            return Action::TooLong {
                limit: self.max_bytes,
            };
        }
        if escaped && !echo {
            return Action::Escaped;
        }
        self.remember(&text);
        Action::Line(text)
    }

    /// Ctrl-C: the cursor goes to the end of the line (where the session prints `^C`).
    fn interrupt(&mut self, echo: bool, out: &mut Vec<u8>) -> Action {
        let right = self.line.len() - self.cursor;
        if echo && right > 0 {
            out.extend_from_slice(format!("\x1b[{right}C").as_bytes());
        }
        self.overflow = false;
        self.clear();
        Action::Interrupt
    }

    fn ctrl_d(&mut self, echo: bool, out: &mut Vec<u8>) -> Option<Action> {
        if self.line.is_empty() && !self.overflow {
            return Some(Action::Eof);
        }
        if echo && self.cursor < self.line.len() {
            self.kill(self.cursor, self.cursor + 1, echo, out);
        }
        None
    }

    fn clear(&mut self) {
        self.line.clear();
        self.line.shrink_to(256);
        self.bytes = 0;
        self.cursor = 0;
        self.utf8.clear();
        self.keys.reset();
        self.escaped = false;
        self.browsing = None;
    }

    fn utf8_byte(&mut self, b: u8, echo: bool, out: &mut Vec<u8>) {
        if b >= 0xC0 {
            self.utf8.clear();
        }
        self.utf8.push(b);
        match std::str::from_utf8(&self.utf8) {
            Ok(s) => {
                let c = s.chars().next().expect("one character");
                self.utf8.clear();
                // A C1 control (U+0080-U+009F, e.g. U+009B, the 8-bit CSI) is no character.
                if !c.is_control() {
                    self.insert(c, echo, out);
                }
            }
            Err(e) if e.error_len().is_some() || self.utf8.len() >= 4 => self.utf8.clear(),
            Err(_) => {}
        }
    }

    fn insert(&mut self, c: char, echo: bool, out: &mut Vec<u8>) {
        if self.overflow || self.bytes + c.len_utf8() > self.max_bytes {
            // Drop the line now (memory stays bounded); Enter reports it.
            self.overflow = true;
            self.line = Vec::new();
            self.bytes = 0;
            self.cursor = 0;
            return;
        }
        self.line.insert(self.cursor, c);
        self.bytes += c.len_utf8();
        self.cursor += 1;
        if echo {
            if self.cursor == self.line.len() {
                // The HMI writes only ASCII: a non-ASCII character shows as one `?`.
                let shown = if c.is_ascii() {
                    c
                } else {
                    super::render::NON_ASCII
                };
                out.push(shown as u8);
            } else {
                self.redraw(out);
            }
        }
    }

    fn backspace(&mut self, echo: bool, out: &mut Vec<u8>) {
        if self.cursor == 0 {
            return;
        }
        if echo && self.cursor == self.line.len() {
            let c = self.line.pop().expect("cursor > 0");
            self.bytes -= c.len_utf8();
            self.cursor -= 1;
            out.extend_from_slice(b"\x08 \x08");
        } else {
            self.kill(self.cursor - 1, self.cursor, echo, out);
        }
    }

    /// Remove `line[from..to]` and leave the cursor at `from`.
    fn kill(&mut self, from: usize, to: usize, echo: bool, out: &mut Vec<u8>) {
        if from >= to {
            return;
        }
        let removed: usize = self.line.drain(from..to).map(char::len_utf8).sum();
        self.bytes -= removed;
        self.cursor = from;
        if echo {
            self.redraw(out);
        }
    }

    fn move_to(&mut self, pos: usize, out: &mut Vec<u8>) {
        if pos != self.cursor {
            self.cursor = pos;
            self.redraw(out);
        }
    }

    /// A cursor or editing key: `ESC [ <params> <b>` or `ESC O <b>`.
    fn key(&mut self, k: Csi, out: &mut Vec<u8>) {
        match (k.last, k.params()) {
            (b'A', _) => self.history_step(true, out),
            (b'B', _) => self.history_step(false, out),
            (b'C', _) => self.move_to((self.cursor + 1).min(self.line.len()), out),
            (b'D', _) => self.move_to(self.cursor.saturating_sub(1), out),
            (b'H', _) | (b'~', "1" | "7") => self.move_to(0, out),
            (b'F', _) | (b'~', "4" | "8") => self.move_to(self.line.len(), out),
            (b'~', "3") if self.cursor < self.line.len() => {
                self.kill(self.cursor, self.cursor + 1, true, out);
            }
            _ => {}
        }
    }

    fn remember(&mut self, text: &str) {
        let text = text.trim();
        if text.is_empty() || self.history.back().is_some_and(|l| l == text) {
            return;
        }
        if text.len() > HISTORY_BYTES || holds_secret(text) {
            return;
        }
        self.history.push_back(text.to_string());
        self.history_bytes += text.len();
        while self.history.len() > HISTORY_LINES || self.history_bytes > HISTORY_BYTES {
            let old = self.history.pop_front().expect("not empty");
            self.history_bytes -= old.len();
        }
    }

    fn history_step(&mut self, back: bool, out: &mut Vec<u8>) {
        let n = self.history.len();
        let pos = match (&self.browsing, back) {
            (None, true) if n > 0 => n - 1,
            (Some((i, _)), true) if *i > 0 => i - 1,
            (Some((i, _)), false) if i + 1 < n => i + 1,
            (Some(_), false) => {
                // Past the newest: back to the line that was being typed.
                let (_, typed) = self.browsing.take().expect("browsing");
                self.set_line(typed, None, out);
                return;
            }
            _ => return,
        };
        let typed = match self.browsing.take() {
            Some((_, typed)) => typed,
            None => std::mem::take(&mut self.line),
        };
        let line = self.history[pos].chars().collect();
        self.browsing = Some((pos, typed));
        self.set_line(line, None, out);
    }

    /// Replace the line; the cursor goes to `cursor` (default: the end).
    fn set_line(&mut self, line: Vec<char>, cursor: Option<usize>, out: &mut Vec<u8>) {
        self.bytes = line.iter().map(|c| c.len_utf8()).sum();
        self.cursor = cursor.unwrap_or(line.len()).min(line.len());
        self.line = line;
        self.redraw(out);
    }

    /// Tab: complete the word before the cursor when it is the first word, or the word after
    /// `help`; list the candidates when there are several.
    fn complete(&mut self, out: &mut Vec<u8>) {
        let before: String = self.line[..self.cursor].iter().collect();
        let partial = match before.rsplit_once(' ') {
            None => before.as_str(),
            Some((head, word)) if head.trim() == "help" => word,
            Some(_) => return,
        };
        // `line` is counted in characters, `before` in bytes: start from the character count.
        let start = self.cursor - partial.chars().count();
        let candidates: Vec<&str> = self
            .words
            .iter()
            .copied()
            .filter(|w| w.starts_with(&partial.to_ascii_lowercase()))
            .collect();
        let Some(first) = candidates.first() else {
            return;
        };
        let common = candidates.iter().fold(first.len(), |n, w| {
            first
                .bytes()
                .zip(w.bytes())
                .take(n)
                .take_while(|(a, b)| a == b)
                .count()
        });
        let mut completed: String = first[..common].to_string();
        if candidates.len() == 1 {
            completed.push(' ');
        }
        if completed.len() > partial.len() || candidates.len() == 1 {
            let rest: Vec<char> = self.line[self.cursor..].to_vec();
            let mut line: Vec<char> = self.line[..start].to_vec();
            line.extend(completed.chars());
            let cursor = line.len();
            line.extend(rest);
            self.set_line(line, Some(cursor), out);
        } else {
            out.extend_from_slice(b"\r\n");
            out.extend_from_slice(candidates.join("  ").as_bytes());
            out.extend_from_slice(b"\r\n");
            self.redraw(out);
        }
    }
}

/// A line that presents the shared secret (`authenticate ...`, or its JSON form): never kept
/// in the history, so the next person at the terminal cannot call it back.
fn holds_secret(line: &str) -> bool {
    let first = line.split_whitespace().next().unwrap_or_default();
    first.eq_ignore_ascii_case("authenticate") || (line.starts_with('{') && line.contains("secret"))
}

#[cfg(test)]
mod tests;
