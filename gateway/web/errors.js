// The errors list `#errors`: safety errors with the protocol's words and what to do, refused
// commands and notices; the newest first, the current safety error marked until it is cleared.

const MAX_ERRORS = 20;

const HINTS = {
  following_error: 'an axis could not follow its command: something blocked it, or it is overloaded; remove the cause',
  overload: 'an axis whose motor is hot (i2t) could not hold with its derated current: the drives of the braked axes are off and their brakes hold the arm; let the motor cool',
  position_limit: 'a joint went beyond its limit; once held, move it back inside its range',
  velocity_limit: 'a joint moved faster than its limit',
  braking_distance: 'a joint could no longer stop before its limit',
  drive_disconnected: 'a drive does not answer on the bus: check its cable and power',
  drive_fault: 'a drive reported a fault',
  emergency_stop: 'the emergency stop was pressed: release it first',
};

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
    head.textContent = `${time}  ${command ? `${command} refused or failed` : 'notice'}`;
  }
  const text = document.createElement('div');
  text.className = 'message';
  text.textContent = msg.error_message || JSON.stringify(msg);
  li.append(head, text);
  if (msg.check !== undefined) {
    const todo = document.createElement('div');
    todo.className = 'todo';
    const hint = HINTS[msg.check] ? `${HINTS[msg.check]}; ` : '';
    todo.textContent = `What to do: ${hint}once the cause is gone, press Hold to clear the error (the protocol's \`hold\`).`;
    li.appendChild(todo);
  }
  ul.prepend(li);
  while (ul.children.length > MAX_ERRORS) ul.lastElementChild.remove();
}

/** The mode is no longer ERROR: no error is current. */
export function clearCurrent() {
  document.querySelectorAll('#errors li.current').forEach((li) => li.classList.remove('current'));
}
