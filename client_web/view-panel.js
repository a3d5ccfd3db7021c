// The camera panel: one picker for the scene's cameras and the user's saved views, Home, undo and
// redo of camera moves (buttons, Ctrl+Z, Ctrl+Shift+Z or Ctrl+Y), fly mode (button or F), and
// saving, forgetting, downloading and uploading named views.

import { isTyping } from './controls.js';
import { checkSavedView, parseSavedViews, savedViewsJson, ViewHistory } from './views.js';

const $ = (selector) => document.querySelector(selector);
const SAVED_PREFIX = 'saved:';

export class ViewPanel {
  // options: getView(), setView(view) (sends it; the picker shows no entry afterwards unless
  // told), sceneCamera(index) (jumps to a scene camera with its focus), home(), saved (the
  // saved views, a list this panel edits), onSavedChange(), showError(message) (null clears).
  constructor(options) {
    this.options = options;
    this.history = new ViewHistory();
    this.flying = false;
    this.picker = $('#cameras');
    this.picker.addEventListener('change', () => this.picked());
    $('#home').addEventListener('click', () => this.move(() => options.home()));
    $('#undo').addEventListener('click', () => this.undo());
    $('#redo').addEventListener('click', () => this.redo());
    $('#fly').addEventListener('click', () => this.setFlying(!this.flying));
    $('#save-view').addEventListener('click', () => this.save());
    $('#view-name').addEventListener('keydown', (e) => { if (e.key === 'Enter') this.save(); });
    $('#forget-view').addEventListener('click', () => this.forget());
    $('#export-views').addEventListener('click', () => this.download());
    $('#import-views').addEventListener('click', () => $('#views-file').click());
    $('#views-file').addEventListener('change', (e) => this.upload(e.target));
    window.addEventListener('keydown', (e) => this.key(e));
    this.listSaved();
  }

  // The scene's cameras, once the welcome is known.
  setSceneCameras(cameras) {
    const group = $('#scene-cameras');
    group.replaceChildren();
    for (const [index, camera] of cameras.entries())
      group.append(new Option(camera.name || `camera ${index + 1}`, index));
  }

  listSaved() {
    const group = $('#saved-views');
    group.replaceChildren();
    for (const [index, view] of this.options.saved.entries())
      group.append(new Option(view.name, SAVED_PREFIX + index));
    group.hidden = this.options.saved.length === 0;
    this.updateButtons();
  }

  // The view moved by other means than this panel: the picker no longer names it.
  viewMoved() {
    if (this.picker.value !== '') {
      this.picker.value = '';
      this.updateButtons();
    }
  }

  // A camera move is about to start: the view before it can be undone.
  moveStarts() {
    this.history.record(this.options.getView());
    this.updateButtons();
  }

  move(change) {
    this.moveStarts();
    change();
  }

  undo() {
    const view = this.history.undo(this.options.getView());
    if (view) this.options.setView(view);
    this.updateButtons();
  }

  redo() {
    const view = this.history.redo(this.options.getView());
    if (view) this.options.setView(view);
    this.updateButtons();
  }

  setFlying(on) {
    this.flying = on;
    $('#fly').setAttribute('aria-pressed', String(on));
    document.body.classList.toggle('flying', on);
  }

  key(event) {
    const command = event.ctrlKey || event.metaKey;
    // A select has no undo of its own: Ctrl+Z there is the camera's.
    const select = event.target instanceof HTMLSelectElement;
    if ((isTyping(event.target) && !(command && select)) || event.altKey) return;
    const key = event.key.toLowerCase();
    if (command && key === 'z') this[event.shiftKey ? 'redo' : 'undo']();
    else if (command && key === 'y') this.redo();
    else if (!command && key === 'f' && !event.repeat) this.setFlying(!this.flying);
    else if (!command && key === 'escape' && this.flying) this.setFlying(false);
    else return;
    event.preventDefault();
  }

  picked() {
    const value = this.picker.value;
    this.updateButtons();
    if (value === '') return;
    this.moveStarts();
    if (value.startsWith(SAVED_PREFIX)) {
      const { name, ...view } = this.options.saved[Number(value.slice(SAVED_PREFIX.length))];
      this.options.setView(view);
    } else {
      this.options.sceneCamera(Number(value));
    }
    this.picker.value = value; // setView cleared it: the view is this entry's
    this.updateButtons();
  }

  save() {
    const input = $('#view-name');
    const name = input.value.trim() || `view ${this.options.saved.length + 1}`;
    let entry;
    try {
      entry = checkSavedView({ name, ...this.options.getView() });
    } catch (error) {
      return this.options.showError(error.message);
    }
    const saved = this.options.saved;
    const existing = saved.findIndex((v) => v.name === entry.name);
    if (existing >= 0) saved[existing] = entry; // the same name: the newer view
    else saved.push(entry);
    input.value = '';
    this.options.showError(null);
    this.listSaved();
    this.picker.value = SAVED_PREFIX + saved.indexOf(entry);
    this.updateButtons();
    this.options.onSavedChange();
  }

  forget() {
    if (!this.picker.value.startsWith(SAVED_PREFIX)) return;
    this.options.saved.splice(Number(this.picker.value.slice(SAVED_PREFIX.length)), 1);
    this.listSaved();
    this.picker.value = '';
    this.updateButtons();
    this.options.onSavedChange();
  }

  download() {
    const blob = new Blob([savedViewsJson(this.options.saved)], { type: 'application/json' });
    const link = Object.assign(document.createElement('a'),
      { href: URL.createObjectURL(blob), download: 'hdof-views.json' });
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 10000);
  }

  async upload(input) {
    const file = input.files?.[0];
    input.value = '';
    if (!file) return;
    try {
      const views = parseSavedViews(await file.text());
      const saved = this.options.saved;
      for (const view of views) {
        const existing = saved.findIndex((v) => v.name === view.name);
        if (existing >= 0) saved[existing] = view;
        else saved.push(view);
      }
      this.options.showError(null);
      this.listSaved();
      this.options.onSavedChange();
    } catch (error) {
      this.options.showError(`${file.name}: ${error.message}`);
    }
  }

  updateButtons() {
    $('#undo').disabled = !this.history.canUndo;
    $('#redo').disabled = !this.history.canRedo;
    const forget = $('#forget-view');
    forget.disabled = !this.picker.value.startsWith(SAVED_PREFIX);
    forget.title = forget.disabled ? 'Pick a saved view above to forget it' : 'Forget the saved view picked above';
    $('#export-views').disabled = this.options.saved.length === 0;
    $('#export-views').title = this.options.saved.length
      ? 'Download the saved views as JSON' : 'No saved views yet: save one first';
  }
}
