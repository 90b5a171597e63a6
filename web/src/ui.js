// Small page helpers: the message line and downloads.

const message = () => document.getElementById('message');

/** Shows `text` on the page (an error unless `kind` is 'info'). */
export function showMessage(text, kind = 'error') {
  const m = message();
  m.textContent = text;
  m.className = kind === 'info' ? 'message info' : 'message';
  m.hidden = false;
  // A warning, not an error: the tests fail on console errors, and this one is handled.
  if (kind !== 'info') console.warn(`tessella viewer: ${text}`);
}

export function clearMessage() {
  message().hidden = true;
}

/** Offers `bytes` as a download called `name`. */
export function download(name, bytes, type) {
  const url = URL.createObjectURL(new Blob([bytes], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
