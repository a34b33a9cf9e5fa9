// The errors list `#errors`: safety errors with the protocol's words and what to do, refused
// commands and notices; the newest first, the current safety error marked until it is cleared.
// What to do comes from the error's code (`error_code`, the contract's table in `codes.js`).

import { ERROR_CODES } from './codes.js';

const MAX_ERRORS = 20;

export function addError(msg, command) {
  const ul = document.querySelector('#errors');
  ul.querySelector('li.none')?.remove();
  if (msg.check !== undefined) {
    ul.querySelectorAll('li.current').forEach((x) => x.classList.remove('current'));
  }
  const li = document.createElement('li');
  li.className = msg.check !== undefined ? 'error current' : 'error';
  const time = new Date().toLocaleTimeString();
  const head = document.createElement('div');
  head.className = 'head';
  if (msg.check !== undefined) {
    li.dataset.check = msg.check;
    if (msg.axis !== undefined) li.dataset.axis = String(msg.axis);
    head.textContent = `${time}  safety check ${msg.check}${msg.axis ? `, axis ${msg.axis}` : ''}`;
  } else {
    li.classList.add(command ? 'refused' : 'notice');
    if (command) li.dataset.command = command;
    // `outcome`: refused, failed, invalid or unknown (may or may not have run).
    const outcome = msg.outcome ? `${command}: ${msg.outcome}` : `${command} refused or failed`;
    head.textContent = `${time}  ${command ? outcome : 'notice'}`;
  }
  if (msg.error_code) {
    li.dataset.code = msg.error_code;
    head.textContent += ` [${msg.error_code}]`;
  }
  const text = document.createElement('div');
  text.className = 'message';
  text.textContent = msg.error_message || JSON.stringify(msg);
  li.append(head, text);
  const remedy = ERROR_CODES[msg.error_code]?.remedy;
  if (msg.check !== undefined || remedy) {
    const todo = document.createElement('div');
    todo.className = 'todo';
    const hold = msg.check !== undefined
      ? 'Once the cause is gone, press Hold to clear the error (the protocol\'s `hold`).'
      : undefined;
    todo.textContent = ['What to do:', remedy, hold].filter(Boolean).join(' ');
    li.appendChild(todo);
  }
  ul.prepend(li);
  while (ul.children.length > MAX_ERRORS) ul.lastElementChild.remove();
}

/** The mode is no longer ERROR: no error is current. */
export function clearCurrent() {
  document.querySelectorAll('#errors li.current').forEach((li) => li.classList.remove('current'));
}
