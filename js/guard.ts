// The guard of the wasm-bindgen glue, shared by the package's entry ("bunraku", js/index.ts:
// the full build) and the playback build ("bunraku/player", js/player.ts), so that no
// mistake of the caller can leave an object borrowed or the module's stack short.
//
//
// Why a guard: an exception that unwinds through wasm frames skips Rust's clean-up. The
// object stays borrowed (every later call throws "recursive use of an object detected" and
// `free()` fails, so it leaks), and the shadow-stack pointer is not restored (after about
// 20,000 such calls the next valid one fails with "memory access out of bounds" and the
// instance is dead). Such exceptions come from the caller's code running while Rust reads
// an argument (a getter or a Proxy trap that throws), from a detached buffer, and from
// wasm-bindgen's own check of a freed object. So before a call enters wasm, this module:
//
// 1. checks that the module was initialised (`not-initialized`), and that the object and
//    every bunraku object among the arguments has not been freed (`freed`);
// 2. copies the arguments into plain data (`plainArguments`): objects and arrays read once,
//    property by property, within a nesting depth and a size (`too-large`); typed arrays
//    as they are (they have no getters of their own to throw). An exception thrown while
//    reading becomes an `unreadable` error that names the path (`options.kinds[2]`), with
//    the exception as its `cause`; a detached typed array is a `bad-type` error.
//
// Then no caller's code runs inside wasm, and every error is a `BunrakuError` with a code.
// The guards are installed on the glue's classes themselves (their prototypes and static
// functions, `guardGlue`), so objects made by any entry point are guarded once the entry is
// loaded.

import type { ErrorCode } from "../pkg/bunraku.js";

/** The deepest nesting of arrays and objects an argument may have (a puppet document nests
 *  four deep; options three). */
export const MAX_NESTING = 32;

/** The most values (array items and object properties, counted through every level) the
 *  arguments of one call may hold in plain arrays and objects: 2²⁰, a puppet document of a
 *  100k-vertex mesh with a pose or two (copied in well under 0.1 s). Bulk data belongs in
 *  typed arrays, which are not counted, and large documents in their JSON text, which is
 *  not copied. */
export const MAX_PLAIN_VALUES = 1 << 20;

/** A `BunrakuError`, made the way the Rust side makes them: a real `Error` with a `code`
 *  and its properties. */
function bunrakuError(code: ErrorCode, message: string, properties: Record<string, unknown> = {}): Error {
  return Object.assign(new Error(message), { code }, properties);
}

/** What a glue object holds: its pointer into wasm memory, 0 once freed. */
interface Wrapped {
  __wbg_ptr: number;
}

export type Class = { name: string; prototype: object } & Record<string, unknown>;

/** The guarded glues' classes (the full build's and the playback build's: `guardGlue`). */
const CLASSES: Class[] = [];

/** Their prototypes: whether a value is an object of one of the glue's classes. */
const PROTOTYPES = new Set<object>();

/** Whether one glue's module was instantiated (its `init` or `initSync` resolved). */
export interface GlueState {
  initialised: boolean;
}

function isBunrakuObject(value: unknown): value is Wrapped {
  // Fast answers first (every call checks its arguments): no primitive and no typed array
  // is one, and neither walks a prototype chain or reaches a Proxy's traps.
  if (value === null || typeof value !== "object" || ArrayBuffer.isView(value)) return false;
  // `instanceof` by hand: the prototype chain against the classes' prototypes (a set), which
  // is 10–100 times faster than `instanceof` against each class once the guards have made
  // the classes' constructors dictionaries.
  try {
    for (let p = Object.getPrototypeOf(value) as object | null; p !== null; p = Object.getPrototypeOf(p) as object | null) {
      if (PROTOTYPES.has(p)) return true;
    }
    return false;
  } catch {
    return false;
  }
}

function checkInitialised(state: GlueState, call: string): void {
  if (!state.initialised) {
    throw bunrakuError(
      "not-initialized",
      `${call}: bunraku is not initialised yet: await init() (or call initSync()) before using it`,
    );
  }
}

function checkAlive(object: unknown, call: string, what: string): void {
  if (isBunrakuObject(object) && object.__wbg_ptr === 0) {
    throw bunrakuError("freed", `${call}: ${what} was freed (free() was called on it) and cannot be used`, {
      argument: what,
    });
  }
}

/** Whether `buffer` was detached (transferred). `ArrayBuffer.prototype.detached` is newer
 *  than Node 20; a detached buffer also refuses `slice`. */
function isDetached(buffer: ArrayBufferLike): boolean {
  if ("detached" in buffer) return Boolean((buffer as { detached: boolean }).detached);
  try {
    buffer.slice(0, 0);
    return false;
  } catch {
    return true;
  }
}

/** How arguments are read: the values still allowed, and for a document given as an object
 *  (`Player.load`, `Track.fromJSON`, `Mesh.fromJSON`) the error it reports for what JSON
 *  cannot hold. */
interface Reading {
  left: number;
  json?: { code: ErrorCode; what: string };
}

/** The intrinsic `length` and `Symbol.toStringTag` getters of typed arrays, which no own
 *  property or subclass can replace. */
const TypedArrayPrototype = Object.getPrototypeOf(Int8Array.prototype) as object;
const intrinsicLength = Object.getOwnPropertyDescriptor(TypedArrayPrototype, "length")!.get!;
const intrinsicTag = Object.getOwnPropertyDescriptor(TypedArrayPrototype, Symbol.toStringTag)!.get!;
const TYPED_ARRAYS: Record<string, new (buffer: ArrayBufferLike, offset: number, length: number) => ArrayBufferView> = {
  Int8Array, Uint8Array, Uint8ClampedArray, Int16Array, Uint16Array, Int32Array, Uint32Array,
  Float32Array, Float64Array, BigInt64Array, BigUint64Array,
};

/** A typed array as it is, or, when it has its own `length` or is of a subclass (whose
 *  getters could throw or lie inside wasm), a plain view of the same memory. */
function typedArray(value: ArrayBufferView, path: string): ArrayBufferView {
  const tag = intrinsicTag.call(value) as string | undefined;
  const Type = tag === undefined ? undefined : TYPED_ARRAYS[tag];
  if (!Type) return value; // a DataView: the binding refuses it by type
  const length = intrinsicLength.call(value) as number;
  // A detached buffer (transferred to a worker) reads as empty, and copying from it
  // throws inside wasm: say what happened instead.
  if (length === 0 && isDetached(value.buffer)) {
    throw bunrakuError("bad-type", `${path}: its buffer is detached (it was transferred, e.g. by postMessage): a ${tag} with data is needed`, {
      argument: path,
      type: `detached ${tag}`,
    });
  }
  if (Object.getPrototypeOf(value) === Type.prototype && !Object.hasOwn(value, "length")) return value;
  return new Type(value.buffer, value.byteOffset, length);
}

/** A coded error for what a document given as an object holds that JSON cannot. */
function notJson(reading: Reading, path: string, what: string): Error {
  const { code, what: document } = reading.json!;
  return bunrakuError(code, `${document}: ${path}: ${what}, which JSON cannot hold`, { field: path });
}

/** The path of `key` in `parent` (`options.kinds`, `poses[3]`), built only when needed:
 *  for an error, or for a container whose items may need it. */
function pathOf(parent: string, key: string | number): string {
  if (typeof key === "number") return `${parent}[${key}]`;
  return parent && key ? `${parent}.${key}` : parent || key;
}

/** Checks a primitive (in a document: a finite number, no function, symbol or bigint). */
function primitive(value: unknown, parent: string, key: string | number, reading: Reading): unknown {
  if (reading.json) {
    if (typeof value === "number" && !Number.isFinite(value)) throw notJson(reading, pathOf(parent, key), `${value} is not finite`);
    if (typeof value === "symbol" || typeof value === "bigint") throw notJson(reading, pathOf(parent, key), `a ${typeof value}`);
  }
  return value;
}

/** Reads `value`, item `key` of `parent`, once into plain data: see the file's comment. */
function plain(value: unknown, parent: string, key: string | number, depth: number, reading: Reading): unknown {
  if (typeof value === "function") {
    if (reading.json) throw notJson(reading, pathOf(parent, key), "a function");
    return value;
  }
  if (value === null || typeof value !== "object") return primitive(value, parent, key, reading);
  if (isBunrakuObject(value)) return value;
  const path = pathOf(parent, key);
  if (ArrayBuffer.isView(value)) {
    // A document holds JSON arrays, which JSON.stringify would not make of a typed array.
    if (reading.json) throw notJson(reading, path, `a ${intrinsicTag.call(value) ?? "DataView"}`);
    return typedArray(value, path);
  }
  if (value instanceof ArrayBuffer) return value;
  if (depth >= MAX_NESTING) {
    throw bunrakuError("too-large", `${path}: nests deeper than ${MAX_NESTING} arrays or objects (the nesting limit)`, {
      field: path,
      limit: MAX_NESTING,
    });
  }
  const count = (n: number): void => {
    reading.left -= n;
    if (reading.left < 0) {
      throw bunrakuError(
        "too-large",
        `${path}: holds more than ${MAX_PLAIN_VALUES} values in arrays and objects (the size limit: put bulk data in typed arrays, and pass a large document as its JSON text)`,
        { field: path, limit: MAX_PLAIN_VALUES },
      );
    }
  };
  if (Array.isArray(value)) {
    const length = value.length;
    count(length);
    const out = new Array(length);
    for (let i = 0; i < length; i++) {
      const item: unknown = value[i];
      if (item === undefined && reading.json) throw notJson(reading, pathOf(path, i), "undefined (or a hole)");
      out[i] = item !== null && (typeof item === "object" || typeof item === "function") ? plain(item, path, i, depth + 1, reading) : primitive(item, path, i, reading);
    }
    return out;
  }
  const keys = Object.keys(value);
  count(keys.length);
  const out: Record<string, unknown> = {};
  for (const name of keys) {
    const item = plain((value as Record<string, unknown>)[name], path, name, depth + 1, reading);
    // A key "__proto__" is an own property, as it was given, not the copy's prototype.
    if (name === "__proto__") Object.defineProperty(out, name, { value: item, enumerable: true, writable: true, configurable: true });
    else out[name] = item;
  }
  return out;
}

/** The functions whose first argument is a document, given as an object or its JSON text:
 *  an object is read strictly (what JSON cannot hold is an error naming its path, never
 *  `null` or dropped as `JSON.stringify` would) and passed on as its JSON text. */
const DOCUMENTS: Record<string, { code: ErrorCode; what: string; root: string; list?: boolean }> = {
  "Player.load": { code: "bad-document", what: "puppet document", root: "" },
  "Track.fromJSON": { code: "bad-document", what: "puppet document", root: "track" },
  "Mesh.fromJSON": { code: "bad-json", what: "mesh JSON", root: "" },
  // A channel's keys: an array.
  "KeyTrack.fromJSON": { code: "bad-document", what: "puppet document", root: "keys", list: true },
};

/** The arguments of `call` as plain data (see `plain`), or a coded error. `names` are the
 *  parameters' names as the declarations spell them. */
function plainArguments(call: string, names: string[], args: unknown[]): unknown[] {
  const reading: Reading = { left: MAX_PLAIN_VALUES };
  const document = DOCUMENTS[call];
  return args.map((arg, i) => {
    const name = names[i] ?? `arguments[${i}]`;
    try {
      if (document && i === 0 && typeof arg === "object" && arg !== null && (document.list || !Array.isArray(arg))) {
        const json: Reading = { left: MAX_PLAIN_VALUES, json: document };
        // Fields are named from the document's root: "track.times[3]", "poses[0]".
        return JSON.stringify(plain(arg, "", document.root, 0, json));
      }
      return plain(arg, "", name, 0, reading);
    } catch (error) {
      if (error instanceof Error && "code" in error) throw error;
      const reason = error instanceof Error ? error.message : String(error);
      throw bunrakuError("unreadable", `${call}: ${name} could not be read (${reason})`, {
        argument: name,
        cause: error,
      });
    }
  });
}

/** The parameter names of a glue function, from its source (`compile(handles, options)`),
 *  for messages. */
function parameterNames(fn: (...args: never[]) => unknown): string[] {
  const match = /^[^(]*\(([^)]*)\)/.exec(Function.prototype.toString.call(fn));
  return match?.[1] ? match[1].split(",").map((s) => s.trim().replace(/=.*$/, "").trim()) : [];
}

export type AnyFunction = (this: unknown, ...args: unknown[]) => unknown;

/** `fn` guarded: initialised, `this` and every bunraku argument alive, arguments plain. */
export function guarded(state: GlueState, call: string, fn: AnyFunction, isMethod: boolean): AnyFunction {
  const names = parameterNames(fn);
  return function (this: unknown, ...args: unknown[]) {
    checkInitialised(state, call);
    if (isMethod) checkAlive(this, call, "the object");
    const copies = plainArguments(call, names, args);
    // Checked after reading: a getter among the arguments may have freed them.
    if (isMethod) checkAlive(this, call, "the object");
    copies.forEach((arg, i) => checkAlive(arg, call, names[i] ?? `arguments[${i}]`));
    try {
      return fn.apply(this, copies);
    } catch (error) {
      throw coded(error, call, names, copies);
    }
  };
}

/** The glue's own check of a class argument (`Puppet.fromMesh(undefined)`) throws a plain
 *  `Error("expected instance of Mesh")` before wasm is entered: the same as a coded
 *  `bad-type`. Any other error passes unchanged. */
function coded(error: unknown, call: string, names: string[], args: unknown[]): unknown {
  const expected = error instanceof Error && !("code" in error) ? /^expected instance of (\w+)$/.exec(error.message) : null;
  if (!expected) return error;
  const i = args.findIndex((arg) => !(CLASSES.some((c) => c.name === expected[1] && arg instanceof (c as unknown as new () => unknown))));
  const name = names[i] ?? "an argument";
  const given = args[i] === null ? "null" : typeof args[i] === "object" ? ((args[i] as object).constructor?.name ?? "Object") : typeof args[i];
  return bunrakuError("bad-type", `${call}: ${name}: expected a ${expected[1]}, got ${given}`, { argument: name, type: given });
}

/** Guards every method, accessor and static function of a glue class, in place. */
function guardClass(state: GlueState, cls: Class): void {
  const proto = cls.prototype as Record<string, unknown>;
  for (const [key, descriptor] of Object.entries(Object.getOwnPropertyDescriptors(proto))) {
    if (key === "constructor" || key.startsWith("__")) continue;
    const call = `${cls.name}.${key}`;
    if (key === "free") {
      const free = descriptor.value as AnyFunction;
      // free() twice, or on an object whose call threw, is harmless.
      descriptor.value = function (this: Wrapped) {
        if (this?.__wbg_ptr !== 0) free.call(this);
      };
    } else if (typeof descriptor.value === "function") {
      descriptor.value = guarded(state, call, descriptor.value as AnyFunction, true);
    } else {
      if (descriptor.get) descriptor.get = guarded(state, call, descriptor.get as AnyFunction, true);
      if (descriptor.set) descriptor.set = guarded(state, call, descriptor.set as AnyFunction, true);
    }
    Object.defineProperty(proto, key, descriptor);
  }
  // `using` calls [Symbol.dispose], which the glue sets to the unguarded free.
  if (typeof Symbol.dispose === "symbol" && Symbol.dispose in proto) {
    Object.defineProperty(proto, Symbol.dispose, { value: proto["free"], writable: true, configurable: true });
  }
  for (const key of Object.getOwnPropertyNames(cls)) {
    const value = cls[key];
    if (typeof value !== "function" || key.startsWith("__")) continue;
    cls[key] = guarded(state, `${cls.name}.${key}`, value as AnyFunction, false);
  }
}

/** A class whose `new` is guarded like its methods (the glue's class, so `instanceof` and
 *  every object it makes are the same). */
export function guardConstructor<C extends abstract new (...args: never[]) => unknown>(state: GlueState, cls: C): C {
  const names = parameterNames(cls as unknown as AnyFunction);
  return new Proxy(cls, {
    construct(target, args, newTarget) {
      const call = `new ${cls.name}`;
      checkInitialised(state, call);
      const copies = plainArguments(call, names, args);
      return Reflect.construct(target, copies, newTarget);
    },
  });
}

/** Guards every class of one glue in place, and registers them as bunraku objects. */
export function guardGlue(state: GlueState, classes: Class[]): void {
  for (const cls of classes) {
    CLASSES.push(cls);
    PROTOTYPES.add(cls.prototype as object);
    guardClass(state, cls);
  }
}
