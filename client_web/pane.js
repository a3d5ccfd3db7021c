// A pane: one canvas and its render session. The split view is two panes, each its own session
// on the daemon in its own mode, fed the same camera and lens.

import { Connection } from './connection.js';
import * as protocol from './protocol.js';
import { Viewer } from './viewer.js';

const MIN_SIDE = 16;

export class Pane {
  // element: the pane (its size is the viewport); handlers: onStatus, onWelcome(welcome, pane),
  // onShown(frame, pane), onServerError(error, pane), onTokenNeeded(message, pane).
  constructor(element, handlers) {
    this.element = element;
    this.canvas = element.querySelector('canvas');
    this.handlers = handlers;
    this.limits = { max_width: 1920, max_height: 1080 };
    this.lastShownAt = 0;
    this.viewer = new Viewer(this.canvas, (frame) => this.shown(frame));
    this.connection = new Connection(protocol.sessionUrl(location), {
      onStatus: (status) => handlers.onStatus?.(status, this),
      onWelcome: (welcome) => {
        this.limits = welcome.limits;
        this.viewer.reset();
        // The limits may be smaller than the viewport asked for: ask again within them.
        if (!sameSize(this.viewport(), this.connection.viewport)) this.resize();
        else handlers.onWelcome?.(welcome, this);
      },
      onFrame: (frame) => this.viewer.push(frame),
      onServerError: (error) => handlers.onServerError?.(error, this),
      onTokenNeeded: (message) => handlers.onTokenNeeded?.(message, this),
    });
  }

  get active() {
    return !this.element.hidden;
  }

  // The pane's size in CSS pixels, within the daemon's limits, keeping its aspect.
  viewport() {
    let width = Math.max(MIN_SIDE, Math.round(this.element.clientWidth));
    let height = Math.max(MIN_SIDE, Math.round(this.element.clientHeight));
    const fit = Math.min(1, this.limits.max_width / width, this.limits.max_height / height);
    width = Math.max(MIN_SIDE, Math.floor(width * fit));
    height = Math.max(MIN_SIDE, Math.floor(height * fit));
    return { width, height };
  }

  // A new session when the pane's size changed (a session's viewport is fixed by its hello).
  resize() {
    const viewport = this.viewport();
    if (!this.connection.viewport || !sameSize(viewport, this.connection.viewport))
      this.connection.open(viewport);
  }

  open() {
    this.connection.open(this.viewport());
  }

  close() {
    this.connection.close();
    this.viewer.reset();
  }

  send(message) {
    return this.connection.send(message);
  }

  shown(frame) {
    this.lastShownAt = performance.now();
    this.connection.send(protocol.ack(frame.frame));
    this.handlers.onShown?.(frame, this);
  }

  // The viewport pixel at a point given as fractions of the image ({u, v}, see Viewer).
  viewportPixel({ u, v }) {
    const { width, height } = this.connection.viewport;
    return { x: Math.floor(u * width), y: Math.floor(v * height) };
  }
}

function sameSize(a, b) {
  return a && b && a.width === b.width && a.height === b.height;
}
