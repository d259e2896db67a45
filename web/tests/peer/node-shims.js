// The Node modules gcode-parser names for its file and stream readers, which a page never
// calls (the benchmark uses its string parser): empty stand-ins so it bundles for chromium.
export class Transform {}
export class EventEmitter {}
export const setImmediate = (f, ...a) => setTimeout(() => f(...a), 0);
export default { Transform, EventEmitter, setImmediate };
