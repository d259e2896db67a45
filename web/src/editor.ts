// The G-code editor: a plain textarea for typing, with line numbers, syntax colouring and the
// diagnostics drawn behind it for the visible lines only (so a million-line program scrolls
// as lightly as a short one), and the line the machine or the timeline is at.

import type { Diag } from './api';

const LINE_HEIGHT = 18;
/// Above this size the program is shown read-only, only its visible lines in the page: a
/// browser's textarea takes most of a minute to lay out a million lines.
const LARGE = 2 * 1024 * 1024;

function esc(s: string): string {
  return s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
}

/// One line of G-code as HTML: words by letter, comments, parameters.
export function colourLine(line: string): string {
  let out = '';
  let i = 0;
  while (i < line.length) {
    const ch = line[i];
    if (ch === '(') {
      const j = line.indexOf(')', i);
      const e = j < 0 ? line.length : j + 1;
      out += `<span class="c">${esc(line.slice(i, e))}</span>`;
      i = e;
    } else if (ch === ';') {
      out += `<span class="c">${esc(line.slice(i))}</span>`;
      break;
    } else if (/[A-Za-z]/.test(ch)) {
      let j = i + 1;
      while (j < line.length && /[\s0-9.+\-]/.test(line[j]) && !(line[j] === ' ' && /[A-Za-z(;]/.test(line[j + 1] ?? 'x'))) j++;
      const word = line.slice(i, j);
      const u = ch.toUpperCase();
      const cls = u === 'G' ? 'g' : u === 'M' ? 'm' : 'XYZABCIJKR'.includes(u) ? 'ax' : 'FS'.includes(u) ? 'fs' : u === 'T' ? 't' : u === 'N' ? 'n' : '';
      out += cls ? `<span class="${cls}">${esc(word)}</span>` : esc(word);
      i = j;
    } else if (ch === '#') {
      let j = i + 1;
      while (j < line.length && /[0-9<>_a-zA-Z]/.test(line[j])) j++;
      out += `<span class="p">${esc(line.slice(i, j))}</span>`;
      i = j;
    } else {
      out += esc(ch);
      i++;
    }
  }
  return out;
}

export class Editor {
  private text = document.getElementById('text') as HTMLTextAreaElement;
  private highlight = document.getElementById('highlight') as HTMLPreElement;
  private gutter = document.getElementById('gutter-inner') as HTMLDivElement;
  private current = document.getElementById('current-line') as HTMLDivElement;
  private code = document.getElementById('code') as HTMLDivElement;
  private scroller = document.getElementById('scroller') as HTMLDivElement;
  private spacer = document.getElementById('spacer') as HTMLDivElement;
  private large = false;
  private whole = '';
  private lines: string[] = [];
  private diags = new Map<number, Diag[]>();
  private currentLine = 0;
  private frame = 0;
  onChange: (text: string) => void = () => {};

  constructor() {
    this.text.addEventListener('scroll', () => this.schedule());
    this.scroller.addEventListener('scroll', () => this.schedule());
    this.text.addEventListener('input', () => {
      this.whole = this.text.value;
      this.lines = this.whole.split('\n');
      this.schedule();
      this.onChange(this.text.value);
    });
    new ResizeObserver(() => this.schedule()).observe(this.text);
  }

  get value(): string { return this.whole; }

  /// The element that scrolls: the textarea, or the read-only view of a large program.
  private get pane(): HTMLElement { return this.large ? this.scroller : this.text; }

  set value(v: string) {
    this.whole = v;
    this.large = v.length > LARGE;
    this.code.classList.toggle('large', this.large);
    this.text.value = this.large ? '' : v;
    this.lines = v.split('\n');
    this.spacer.style.height = this.large ? `${this.lines.length * LINE_HEIGHT}px` : '0';
    this.pane.scrollTop = 0;
    this.diags.clear();
    this.schedule();
  }

  setDiagnostics(diags: Diag[]) {
    this.diags.clear();
    for (const d of diags) {
      const l = this.diags.get(d.line) ?? [];
      l.push(d);
      this.diags.set(d.line, l);
    }
    this.schedule();
  }

  /// Mark `line` (1-based; 0 for none) and scroll it into view.
  setCurrentLine(line: number, scroll = true) {
    if (line === this.currentLine) return;
    this.currentLine = line;
    if (scroll && line > 0) {
      const pane = this.pane;
      const top = (line - 1) * LINE_HEIGHT, h = pane.clientHeight;
      if (top < pane.scrollTop || top > pane.scrollTop + h - 2 * LINE_HEIGHT) {
        pane.scrollTop = Math.max(0, top - h / 3);
      }
    }
    this.schedule();
  }

  goTo(line: number, col: number) {
    if (this.large) return this.setCurrentLine(line);
    let pos = 0;
    for (let i = 0; i < line - 1 && i < this.lines.length; i++) pos += this.lines[i].length + 1;
    pos += Math.max(0, col - 1);
    this.text.focus();
    this.text.setSelectionRange(pos, pos);
    this.setCurrentLine(line);
  }

  private schedule() {
    if (!this.frame) this.frame = requestAnimationFrame(() => { this.frame = 0; this.draw(); });
  }

  private draw() {
    const pane = this.pane;
    const top = pane.scrollTop;
    const first = Math.floor(top / LINE_HEIGHT);
    const count = Math.ceil(pane.clientHeight / LINE_HEIGHT) + 1;
    const last = Math.min(this.lines.length, first + count);
    const offset = first * LINE_HEIGHT - top;
    let nums = '';
    for (let i = first; i < last; i++) {
      const d = this.diags.get(i + 1);
      const worst = d && (d.some((x) => x.severity === 'error') ? 'err' : d.some((x) => x.severity === 'warning') ? 'warn' : 'note');
      const cls = worst || '';
      nums += cls ? `<span class="${cls}" title="${esc(d!.map((x) => x.message).join('\n'))}">${i + 1}</span>\n` : `${i + 1}\n`;
    }
    this.gutter.style.top = offset + 'px';
    this.gutter.innerHTML = nums;
    {
      let html = '';
      for (let i = first; i < last; i++) {
        const line = this.lines[i];
        const d = this.diags.get(i + 1);
        if (d) {
          // The marked span of the first diagnostic is underlined.
          const s = Math.max(0, d[0].col - 1), e = Math.max(s + 1, s + d[0].len);
          const kind = d[0].severity === 'note' ? ' note' : '';
          html += colourLine(line.slice(0, s)) + `<span class="squiggle${kind}">${esc(line.slice(s, e) || ' ')}</span>` + colourLine(line.slice(e)) + '\n';
        } else {
          html += colourLine(line) + '\n';
        }
      }
      this.highlight.innerHTML = `<div class="lines" style="top:${offset}px;left:${6 - pane.scrollLeft}px">${html}</div>`;
    }
    if (this.currentLine > 0) {
      this.current.style.display = 'block';
      this.current.style.top = (this.currentLine - 1) * LINE_HEIGHT - top + 'px';
    } else {
      this.current.style.display = 'none';
    }
  }
}
