// One render session over WebSocket: hello/welcome, frames, automatic reconnect with backoff.
// A resize reconnects too: the viewport is fixed by hello for the life of a session.

import * as protocol from './protocol.js';

const BACKOFF_FIRST_MS = 500;
const BACKOFF_MAX_MS = 10000;

export class Connection {
  // handlers: onStatus({state, message, attempt}), onWelcome(welcome), onFrame(frame),
  // onPicked(picked), onServerError(error), onTokenNeeded(message). state: connecting, live,
  // reconnecting (attempt: the reconnection attempts so far), error.
  constructor(url, handlers) {
    this.url = url;
    this.handlers = handlers;
    this.socket = null;
    this.viewport = null;
    this.token = '';
    this.welcome = null;
    this.attempt = 0;
    this.retryTimer = 0;
    this.lastError = null;
    // Why the last session ended, kept while reconnection attempts fail to reach the daemon.
    this.cause = null;
    this.stopped = false;
  }

  get live() {
    return this.welcome !== null && this.socket?.readyState === WebSocket.OPEN;
  }

  // (Re)connects now with this viewport, dropping the current session.
  open(viewport) {
    this.viewport = viewport;
    this.stopped = false;
    clearTimeout(this.retryTimer);
    this.drop();
    this.status('connecting');
    const socket = new WebSocket(this.url, protocol.SUBPROTOCOL);
    socket.binaryType = 'arraybuffer';
    socket.onopen = () => {
      socket.opened = true;
      this.sendRaw(socket, protocol.hello(this.viewport, this.token));
    };
    socket.onmessage = (event) => this.receive(socket, event.data);
    socket.onclose = (event) => this.closed(socket, event);
    this.socket = socket;
  }

  useToken(token) {
    this.token = token;
    this.attempt = 0;
    this.open(this.viewport);
  }

  close() {
    this.stopped = true;
    clearTimeout(this.retryTimer);
    this.drop();
  }

  // Sends a client message on a live session; false when there is none.
  send(message) {
    if (!this.live) return false;
    return this.sendRaw(this.socket, message);
  }

  sendRaw(socket, message) {
    socket.send(JSON.stringify(message));
    return true;
  }

  drop() {
    const socket = this.socket;
    this.socket = null;
    this.welcome = null;
    if (socket && socket.readyState <= WebSocket.OPEN) socket.close(1000, 'client closed');
  }

  status(state, message = '') {
    this.handlers.onStatus?.({ state, message, attempt: this.attempt });
  }

  receive(socket, data) {
    if (socket !== this.socket) return;
    if (data instanceof ArrayBuffer) {
      let frame;
      try {
        frame = protocol.parseFrame(data);
      } catch (error) {
        this.status('error', `bad frame from the server: ${error.message}`);
        return;
      }
      this.handlers.onFrame?.(frame);
      return;
    }
    const message = JSON.parse(data);
    if (message.type === 'welcome') {
      this.welcome = message;
      this.attempt = 0;
      this.lastError = null;
      this.cause = null;
      this.status('live');
      this.handlers.onWelcome?.(message);
    } else if (message.type === 'picked') {
      this.handlers.onPicked?.(message);
    } else if (message.type === 'error') {
      this.lastError = message;
      // Before the welcome an error is about the hello (a close may follow).
      if (!this.welcome) this.status('error', message.message);
      this.handlers.onServerError?.(message);
    }
  }

  closed(socket, event) {
    if (socket !== this.socket) return; // a session we dropped on purpose
    this.socket = null;
    this.welcome = null;
    if (this.stopped) return;
    const reason = this.lastError?.message || event.reason || `closed (${event.code})`;
    const needsToken = this.lastError?.field === 'token';
    this.lastError = null;
    if (event.code === protocol.CLOSE.POLICY) {
      // Only a token can help; a disallowed origin stays disallowed.
      if (needsToken) this.handlers.onTokenNeeded?.(reason);
      this.status('error', reason);
      return;
    }
    const delay = Math.min(BACKOFF_MAX_MS, BACKOFF_FIRST_MS * 2 ** this.attempt++);
    // A socket that never opened did not reach the daemon: the cause is still the one before.
    if (socket.opened) {
      this.cause = event.code === protocol.CLOSE.GOING_AWAY ? 'the daemon stopped' : reason;
    }
    const why = this.cause ?? 'cannot reach the daemon';
    this.status('reconnecting', `${why}; reconnect attempt ${this.attempt} in ${(delay / 1000).toFixed(1)} s`);
    this.retryTimer = setTimeout(() => this.open(this.viewport), delay);
  }
}
