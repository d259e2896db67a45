// The design processes: milling, sole molds, plots and embroidery. Each has a form (fields with units
// and limits, checked by the browser first and by the server's own validation after), takes
// a file uploaded into the job folder, and gives back a program the page loads like any
// other. The forms carry no CAM knowledge: names and defaults are those of `oficina mill`,
// `oficina sole` and `oficina plot`, whose pipelines the server runs.

// A 3D model (.stl/.obj) is carved as `oficina carve MODEL` carves it (/api/model): its mesh
// drawn in the 3D view (carve_model.ts), its stock simulated.
// Embroidery takes a design (.svg/.dxf) to /api/embroider, or a stitch file (.dst/.exp/.pes/.pec/.jef/.vp3/.xxx/.u01/.ram)
// to /api/stitches; its answer is drawn in thread colours, not loaded as a program.
export type ProcessKind = 'mill' | 'sole' | 'plot' | 'embroider' | 'model';
/// Stitch files: read back and shown as they are.
export const STITCH_FILE = /\.(dst|exp|pes|pec|jef|vp3|xxx|u01|ram)$/i;

interface Field {
  name: string; label: string; unit?: string;
  kind?: 'number' | 'text' | 'select' | 'check';
  value: string; min?: number; max?: number; options?: string[]; optional?: boolean; placeholder?: string;
}

export const PROCESSES: Record<ProcessKind, { title: string; accept: RegExp; sample: string; fields: Field[] }> = {
  mill: {
    title: 'Mill (profile/pocket/drill)', accept: /\.(svg|dxf)$/i, sample: 'plate.svg',
    fields: [
      { name: 'op', label: 'Operation', kind: 'select', value: 'pocket', options: ['pocket', 'profile-out', 'profile-in', 'profile-on', 'drill'] },
      { name: 'tool', label: 'Tool', kind: 'text', value: 'flat:3' },
      { name: 'depth', label: 'Depth', unit: 'mm', value: '2', min: 0.01, max: 500 },
      { name: 'stepdown', label: 'Step-down', unit: 'mm', value: '', min: 0.01, max: 100, optional: true },
      { name: 'stepover', label: 'Step-over', unit: 'mm', value: '', min: 0.01, max: 100, optional: true },
      { name: 'strategy', label: 'Pocket strategy', kind: 'select', value: 'offset', options: ['offset', 'zigzag'] },
      { name: 'feed', label: 'Feed', unit: 'mm/min', value: '800', min: 1, max: 100000 },
      { name: 'plunge_feed', label: 'Plunge feed', unit: 'mm/min', value: '', min: 1, max: 100000, optional: true },
      { name: 'rpm', label: 'Spindle', unit: 'rpm', value: '12000', min: 0, max: 100000 },
      { name: 'entry', label: 'Entry', kind: 'select', value: 'ramp', options: ['ramp', 'helix', 'plunge'] },
      { name: 'tabs', label: 'Tabs per contour', value: '0', min: 0, max: 100 },
      { name: 'clear_z', label: 'Clearance Z', unit: 'mm', value: '5', min: 0, max: 1000 },
      { name: 'safe_z', label: 'Safe Z', unit: 'mm', value: '20', min: 0, max: 1000 },
      { name: 'post', label: 'Post', kind: 'select', value: 'linuxcnc', options: ['linuxcnc', 'grbl', 'sinumerik', 'legacy-2006'] },
    ],
  },
  sole: {
    title: 'Sole mold', accept: /\.(csv|txt|xy|pts)$/i, sample: 'size34.csv',
    fields: [
      { name: 'from_size', label: 'Pattern size', value: '34', min: 10, max: 60 },
      { name: 'to_size', label: 'Size to make', value: '37', min: 10, max: 60 },
      { name: 'system', label: 'Size system', kind: 'select', value: 'br', options: ['br', 'us'] },
      { name: 'shrink', label: 'Shrinkage', unit: '%', value: '2', min: 0, max: 20 },
      { name: 'fit_tolerance', label: 'Fit tolerance', unit: 'mm', value: '0.3', min: 0.001, max: 5 },
      { name: 'post', label: 'Post', kind: 'select', value: 'linuxcnc', options: ['linuxcnc', 'grbl', 'sinumerik', 'legacy-2006'] },
    ],
  },
  plot: {
    // HP-GL is read by its content on the server; these are the extensions plotter files carry.
    // Pictures (.png/.jpg) are hatched; opened while Plot is chosen they come here, else to
    // the relief form.
    title: 'Plot', accept: /\.(svg|dxf|hpgl|hpgl2|plt|hpg|hp|hgl|gl|gl2|prn|png|jpe?g)$/i, sample: 'design.svg',
    fields: [
      // Not a plot parameter: the plotter profile the job is made for (and run on).
      { name: 'machine', label: 'Plotter', kind: 'select', value: 'pen-plotter', options: ['pen-plotter', 'polar-plotter', 'polargraph-wall'] },
      // `oficina plot --format`: gcode (grbl family), joint (polar plotters on a plain
      // controller), marlin (Marlin 2.x: M280 servo pen, G28). HP-GL is the CLI's only: the
      // page loads and runs G-code.
      { name: 'format', label: 'Output', kind: 'select', value: 'gcode', options: ['gcode', 'joint', 'marlin'] },
      { name: 'scale', label: 'Scale', unit: '×', value: '1', min: 0.001, max: 10000 },
      // `oficina plot --layout/--landscape/--margin/--no-fit`: vpype's layout on a page.
      { name: 'layout', label: 'Page (layout)', kind: 'text', value: '', optional: true, placeholder: 'none: a4, a3, letter, 300x200, 8.5x11in' },
      { name: 'landscape', label: 'Landscape', kind: 'check', value: '' },
      { name: 'margin', label: 'Margin', unit: 'mm', value: '10', min: 0, max: 1000 },
      { name: 'no_fit', label: 'Keep size (centre only)', kind: 'check', value: '' },
      { name: 'feed', label: 'Drawing feed', unit: 'mm/min', value: '', min: 1, max: 100000, optional: true },
      { name: 'pen', label: 'Pen lift', kind: 'select', value: 'z', options: ['z', 'servo'] },
      { name: 'pens', label: 'Pens by', kind: 'select', value: 'color', options: ['color', 'layer'] },
      { name: 'merge_tol', label: 'Join ends within', unit: 'mm', value: '0.05', min: 0, max: 10 },
      { name: 'text', label: 'Text', kind: 'text', value: '', optional: true },
      { name: 'no_optimise', label: 'Draw as given', kind: 'check', value: '' },
      // `oficina plot --fill/--fill-angle/--fill-spacing/--fill-cross/--fill-concentric/--filled`.
      { name: 'fill', label: 'Hatch fills', kind: 'check', value: '' },
      { name: 'fill_angle', label: 'Hatch angle', unit: '°', value: '45', min: -360, max: 360 },
      { name: 'fill_spacing', label: 'Hatch spacing', unit: 'mm', value: '1', min: 0.05, max: 100 },
      { name: 'fill_cross', label: 'Cross-hatch', kind: 'check', value: '' },
      { name: 'fill_concentric', label: 'Concentric', kind: 'check', value: '' },
      // A picture: `--pixel/--pitch/--hatch-layers/--image-pens`. Without "Hatch fills" its
      // layers are lines at 0/90/45/135° `pitch` apart; with it, its darkness bands are filled
      // by the hatch fields above, band k at spacing/k.
      { name: 'pixel', label: 'Picture pixel', unit: 'mm', value: '0.5', min: 0.001, max: 100 },
      { name: 'pitch', label: 'Picture line pitch', unit: 'mm', value: '1', min: 0.01, max: 100 },
      { name: 'hatch_layers', label: 'Picture layers', value: '3', min: 1, max: 8 },
      { name: 'image_pens', label: 'Picture pens', kind: 'text', value: '', optional: true, placeholder: 'one: #999999,#000000 (lightest first)' },
      // svg: a fill colour; closed: every closed outline; loops: every closed subpath (vpype-occult).
      { name: 'filled', label: 'Filled shapes', kind: 'select', value: 'svg', options: ['svg', 'closed', 'loops'] },
      // `--occult` / `--occult-across`: later filled shapes hide what was drawn under them.
      { name: 'occult', label: 'Hide lines under shapes', kind: 'check', value: '' },
      { name: 'occult_across', label: '… across pens', kind: 'check', value: '' },
      { name: 'passes', label: 'Passes', value: '1', min: 1, max: 100 },
      { name: 'reloop', label: 'Start loops near the pen', kind: 'check', value: '' },
      { name: 'crop', label: 'Crop', kind: 'text', value: '', optional: true, placeholder: 'none: paper, or X0,Y0,X1,Y1 mm' },
    ],
  },
  // Names and defaults are `oficina carve MODEL`'s flags (the CLI checks the ranges alike).
  model: {
    title: 'Carve a 3D model (STL/OBJ)', accept: /\.(stl|obj)$/i, sample: '',
    fields: [
      { name: 'tool', label: 'Finishing tool', kind: 'text', value: 'ball:6' },
      { name: 'rough_tool', label: 'Roughing tool', kind: 'text', value: '', optional: true, placeholder: 'none: flat:6' },
      { name: 'size', label: 'Largest dimension', unit: 'mm', value: '', min: 0.001, max: 10000, optional: true },
      { name: 'scale', label: 'Scale', unit: '×', value: '1', min: 0.0001, max: 10000 },
      { name: 'rotate', label: 'Turn about Z', unit: '°', value: '0', min: -360, max: 360 },
      { name: 'stock_top', label: 'Stock top Z', unit: 'mm', value: '', min: -10000, max: 10000, optional: true, placeholder: "model's top" },
      { name: 'stock_bottom', label: 'Stock bottom Z', unit: 'mm', value: '', min: -10000, max: 10000, optional: true, placeholder: "model's bottom" },
      { name: 'scallop', label: 'Scallop', unit: 'mm', value: '0.02', min: 0.0001, max: 10 },
      { name: 'stepover', label: 'Step-over', unit: 'mm', value: '', min: 0.001, max: 100, optional: true },
      { name: 'rough_stepover', label: 'Roughing step-over', unit: '× Ø', value: '0.8', min: 0.01, max: 1 },
      { name: 'stepdown', label: 'Step-down', unit: 'mm', value: '5', min: 0.01, max: 100 },
      { name: 'allowance', label: 'Allowance', unit: 'mm', value: '0.5', min: 0, max: 100 },
      { name: 'direction', label: 'Raster', kind: 'select', value: 'x', options: ['x', 'y', 'both'] },
      { name: 'angle', label: 'Raster angle', unit: '°', value: '', min: -360, max: 360, optional: true },
      { name: 'strategy', label: 'Finishing', kind: 'select', value: 'raster', options: ['raster', 'waterline', 'mix'] },
      { name: 'steep', label: 'Steep from', unit: '°', value: '45', min: 10, max: 80 },
      { name: 'roughing', label: 'Roughing', kind: 'select', value: 'zlevel', options: ['zlevel', 'heightfield'] },
      { name: 'one_way', label: 'One way', kind: 'check', value: '' },
      { name: 'no_rest', label: 'No rest machining', kind: 'check', value: '' },
      { name: 'feed', label: 'Feed', unit: 'mm/min', value: '2000', min: 1, max: 100000 },
      { name: 'plunge_feed', label: 'Plunge feed', unit: 'mm/min', value: '500', min: 1, max: 100000 },
      { name: 'rpm', label: 'Spindle', unit: 'rpm', value: '18000', min: 0, max: 100000 },
      { name: 'safe_z', label: 'Safe Z', unit: 'mm', value: '5', min: 0, max: 1000 },
      { name: 'tolerance', label: 'Tolerance', unit: 'mm', value: '0.002', min: 0.0001, max: 1 },
      { name: 'pixel_size', label: 'Grid', unit: 'mm', value: '', min: 0.001, max: 100, optional: true },
      { name: 'post', label: 'Post', kind: 'select', value: 'grbl', options: ['grbl', 'linuxcnc'] },
      { name: 'allow_m6', label: 'Machine takes M6', kind: 'check', value: '' },
    ],
  },
  // Names and ranges are `oficina embroider`'s flags and the stitch crate's Params::check.
  embroider: {
    title: 'Embroidery', accept: /\.(svg|dxf|dst|exp|pes|pec|jef|vp3|xxx|u01|ram)$/i, sample: 'sunflower.svg',
    fields: [
      { name: 'stitch_length', label: 'Stitch length', unit: 'mm', value: '2.5', min: 0.1, max: 12.7 },
      { name: 'fill_angle', label: 'Fill angle', unit: '°', value: '0', min: -360, max: 360 },
      { name: 'fill_spacing', label: 'Fill row spacing', unit: 'mm', value: '0.4', min: 0.1, max: 5 },
      { name: 'fill_stitch_length', label: 'Fill stitch length', unit: 'mm', value: '3', min: 0.5, max: 12.1 },
      { name: 'satin_spacing', label: 'Satin spacing', unit: 'mm', value: '0.4', min: 0.1, max: 5 },
      { name: 'satin_min_width', label: 'Satin from width', unit: 'mm', value: '1', min: 0, max: 100 },
      { name: 'pull_compensation', label: 'Pull compensation', unit: 'mm', value: '0.2', min: 0, max: 5 },
      { name: 'trim_length', label: 'Trim jumps over', unit: 'mm', value: '3', min: 0, max: 1000 },
      { name: 'underlay', label: 'Underlay', kind: 'check', value: 'on' },
      { name: 'ties', label: 'Lock stitches', kind: 'check', value: 'on' },
      { name: 'fill_closed', label: 'Fill closed outlines', kind: 'check', value: '' },
      { name: 'hoop', label: 'Hoop', kind: 'text', value: '', optional: true, placeholder: 'smallest that fits (C03, round-150…)' },
      { name: 'format', label: 'File format', kind: 'select', value: 'dst', options: ['dst', 'exp', 'pes', 'pes-v1', 'pec', 'jef', 'vp3', 'xxx', 'u01', 'ram'] },
      // The table the sheet's run and "Sew" use: the seed's, or a motion profile's X/Y limits.
      { name: 'machine', label: 'Embroidery table', kind: 'select', value: 'embroidery-table', options: ['embroidery-table', 'embroidery-xy'] },
      { name: 'ppm', label: 'Fixed head speed', unit: 'stitches/min', value: '', min: 1, max: 10000, optional: true },
      { name: 'pieces', label: 'Pieces', value: '1', min: 1, max: 1000000 },
      // Lettering added to the design, or sewn alone ("Text alone"), as `oficina embroider
      // --text`: '|' starts a line. Masego is made for 14–21 mm capitals (its font.json).
      { name: 'text', label: 'Text', kind: 'text', value: '', optional: true, placeholder: 'Ana|Maria' },
      { name: 'font', label: 'Font', kind: 'select', value: 'masego', options: ['masego'] },
      { name: 'text_size', label: 'Text height', unit: 'mm', value: '15', min: 13.9, max: 20.9 },
      { name: 'text_align', label: 'Text alignment', kind: 'select', value: 'center', options: ['left', 'center', 'right'] },
      // Ink/Stitch's "Add trims": the thread cut after each line, word or letter.
      { name: 'text_trim', label: 'Trim the text', kind: 'select', value: 'never', options: ['never', 'line', 'word', 'letter'] },
      // Both empty: under the design, centred on it (or at its edge as aligned).
      { name: 'text_x', label: 'Text at X', unit: 'mm', value: '', min: -1000, max: 1000, optional: true, placeholder: 'under the design' },
      { name: 'text_y', label: 'Text at Y', unit: 'mm', value: '', min: -1000, max: 1000, optional: true, placeholder: 'under the design' },
    ],
  },
};

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

/// Builds the form of `kind` into #process-form.
export function renderForm(kind: ProcessKind) {
  const p = PROCESSES[kind];
  $('process-title').textContent = p.title;
  const form = $('process-fields');
  form.innerHTML = '';
  for (const f of p.fields) {
    const label = document.createElement('label');
    label.textContent = f.label + ' ';
    let input: HTMLInputElement | HTMLSelectElement;
    if (f.kind === 'select') {
      input = document.createElement('select');
      for (const o of f.options!) input.add(new Option(o, o, o === f.value, o === f.value));
    } else {
      const i = document.createElement('input');
      i.type = f.kind === 'text' ? 'text' : f.kind === 'check' ? 'checkbox' : 'number';
      if (i.type === 'number') {
        i.step = 'any';
        if (f.min !== undefined) i.min = String(f.min);
        if (f.max !== undefined) i.max = String(f.max);
        if (!f.optional) i.required = true;
        if (f.optional) i.placeholder = 'auto';
      }
      i.value = f.value;
      if (i.type === 'checkbox') i.checked = f.value === 'on';
      if (f.placeholder) i.placeholder = f.placeholder;
      input = i;
    }
    input.name = f.name;
    label.appendChild(input);
    if (f.unit) label.append(' ' + f.unit);
    const err = document.createElement('span');
    err.className = 'field-error';
    err.dataset.for = f.name;
    label.appendChild(err);
    form.appendChild(label);
  }
  if (kind === 'plot') penFollowsFormat();
}

/// As `oficina plot`: the pen lift defaults to a servo with --format marlin, else Z.
function penFollowsFormat() {
  const format = document.querySelector<HTMLSelectElement>('#process-fields [name="format"]')!;
  const pen = document.querySelector<HTMLSelectElement>('#process-fields [name="pen"]')!;
  format.addEventListener('change', () => { pen.value = format.value === 'marlin' ? 'servo' : 'z'; });
}

/// The form's values as the server's parameters, or the first field the browser refuses.
export function readForm(kind: ProcessKind): { params: Record<string, unknown> } | { field: string; message: string } {
  const params: Record<string, unknown> = {};
  for (const f of PROCESSES[kind].fields) {
    const el = document.querySelector(`#process-fields [name="${f.name}"]`) as HTMLInputElement | HTMLSelectElement;
    if (el instanceof HTMLInputElement && !el.checkValidity()) return { field: f.name, message: el.validationMessage };
    if (f.kind === 'check') { params[f.name] = (el as HTMLInputElement).checked; continue; }
    if (el.value === '') continue;
    params[f.name] = f.kind === 'select' || f.kind === 'text' ? el.value : Number(el.value);
  }
  return { params };
}

/// A message shown beside its field (or under the form when it names none).
export function showFieldError(field: string | null, message: string) {
  clearFieldErrors();
  const span = field ? document.querySelector(`#process-fields .field-error[data-for="${field}"]`) : null;
  if (span) {
    span.textContent = message;
    span.closest('label')?.classList.add('invalid');
  } else {
    $('process-status').textContent = message;
  }
}

export function clearFieldErrors() {
  document.querySelectorAll('#process-fields .field-error').forEach((s) => { s.textContent = ''; });
  document.querySelectorAll('#process-fields label.invalid').forEach((l) => l.classList.remove('invalid'));
}
