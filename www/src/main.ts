// The demo page: starts the puppet's worker (it loads the wasm module) and the default
// puppet's download at once, picks a renderer, and wires the stage, the toolbar, the
// motion panels (parameters, timeline, swings) and the status panel to the app.

import { attachAnimation } from "./animation.js";
import { App } from "./app.js";
import { CharacterStage, layeredFiles, SAMPLE_CHARACTER } from "./character.js";
import { PuppetWorker } from "./client.js";
import { attachControls, download, sliderDetail } from "./controls.js";
import { exposeHook } from "./hook.js";
import { Overlay } from "./overlay.js";
import { DEFAULT_PUPPET, pictureFromFile, pictureFromURL } from "./picture.js";
import { attachPointer } from "./pointer.js";
import { loadWasm } from "./characterfiles.js";
import { attachParameterPanel } from "./parameterpanel.js";
import { Swings } from "./swing.js";
import { Timeline } from "./timeline.js";
import { METHODS, PIN_KINDS } from "./protocol.js";
import { createRenderer } from "./renderer.js";
import { Status } from "./status.js";

function element<T extends HTMLElement>(id: string, type: new () => T): T {
  const el = document.getElementById(id);
  if (!(el instanceof type)) throw new Error(`the page has no <${type.name}> #${id}`);
  return el;
}

async function main(status: Status): Promise<void> {
  let app: App | null = null;
  // The worker bundle sits next to this one (www/build.mjs builds both).
  const worker = new PuppetWorker(new URL("worker.js", import.meta.url), (error) => app?.workerCrashed(error));
  const firstPicture = pictureFromURL(DEFAULT_PUPPET.url, DEFAULT_PUPPET.name);
  // openPicture reports a failed download; until it is called, the rejection is not
  // "unhandled".
  firstPicture.catch(() => {});

  const stage = element("stage", HTMLCanvasElement);
  const wrap = element("stage-wrap", HTMLElement);
  const density = element("density", HTMLInputElement);
  const methodSelect = element("method", HTMLSelectElement);
  const pinKind = element("pin-kind", HTMLSelectElement);
  const simulation = element("simulation-mesh", HTMLInputElement);
  const overlay = new Overlay(element("overlay", HTMLCanvasElement));
  const query = new URLSearchParams(location.search);
  const choice = query.get("renderer") === "2d" ? "2d" : "auto";
  // ?method= chooses the first method (the selector shows it); the injective one else.
  const method = METHODS.find((m) => m === query.get("method")) ?? "injective";
  methodSelect.value = method;
  const renderer = await createRenderer(stage, choice, (lost) => app?.contextLost(lost));
  app = new App({
    stage,
    renderer,
    overlay,
    status,
    worker,
    density: sliderDetail(density),
    method,
  });
  const theApp = app;
  // Layered characters (character.ts): their own canvas over the stage, meshed and solved
  // on this thread.
  const characters = new CharacterStage(
    {
      canvas: element("character-stage", HTMLCanvasElement),
      overlay: element("character-overlay", HTMLCanvasElement),
      // The picture's stage, and the poses and animation, which act on pictures only.
      pictureLayers: [stage, element("overlay", HTMLCanvasElement), element("animation", HTMLElement), element("motion-timeline", HTMLElement), element("motion-swing", HTMLElement)],
      panel: element("character-panel", HTMLElement),
      order: element("draw-order", HTMLOListElement),
      showGlue: element("show-glue", HTMLInputElement),
      motion: { field: element("character-motion", HTMLElement), slider: element("head-turn", HTMLInputElement), output: element("head-turn-value", HTMLOutputElement) },
    },
    status,
    method,
  );
  characters.setShowPins(element("show-pins", HTMLInputElement).checked);
  /** A character opened: the picture's board lets go of its selection (Delete acts on
   *  the character's pins). */
  const characterOpened = (ok: boolean | "not-layered") => {
    if (ok === true) theApp.board.selected = null;
    return ok;
  };
  element("open-sample", HTMLButtonElement).addEventListener("click", () => {
    status.info(`reading the ${SAMPLE_CHARACTER.name}…`);
    void characters.openURL(SAMPLE_CHARACTER.url, SAMPLE_CHARACTER.name, SAMPLE_CHARACTER.pins).then(characterOpened);
  });
  // What a reload kept of the form.
  theApp.board.pinKind = PIN_KINDS.find((k) => k === pinKind.value) ?? "position";
  // ?simulation=1 shows the simulation mesh from the start.
  if (query.get("simulation") === "1") simulation.checked = true;
  theApp.showSimulation(simulation.checked);

  const measure = () => {
    const r = wrap.getBoundingClientRect();
    theApp.resize(r.width, r.height, window.devicePixelRatio || 1);
    characters.resize(r.width, r.height, window.devicePixelRatio || 1);
  };
  measure();
  new ResizeObserver(measure).observe(wrap);

  attachPointer(stage, theApp.board);
  const controls = attachControls(
    {
      file: element("file", HTMLInputElement),
      density,
      densityValue: element("density-value", HTMLOutputElement),
      method: methodSelect,
      pinKind,
      tools: { pin: element("tool-pin", HTMLInputElement), starch: element("starch", HTMLInputElement), overlap: element("overlap", HTMLInputElement) },
      amounts: {
        starch: { input: element("starch-amount", HTMLInputElement), value: element("starch-amount-value", HTMLOutputElement) },
        overlap: { input: element("overlap-depth", HTMLInputElement), value: element("overlap-depth-value", HTMLOutputElement) },
      },
      clearRegions: element("clear-regions", HTMLButtonElement),
      wireframe: element("wireframe", HTMLInputElement),
      simulation,
      pins: element("show-pins", HTMLInputElement),
      reset: element("reset", HTMLButtonElement),
      export: element("export", HTMLButtonElement),
      exportOverlays: element("export-overlays", HTMLInputElement),
      dropZone: document.body,
    },
    {
      openFiles: (files) => {
        const openPicture = (file: File) => {
          status.info(`reading ${file.name}…`);
          // The user's own picture opens at its full detail (detail.ts); once it is in, it
          // takes the stage from a character.
          void theApp.openPicture(pictureFromFile(file), undefined, { fullDetail: true }).then((ok) => ok && characters.close());
        };
        const [first] = files;
        if (!first) return;
        if (!layeredFiles(files)) return openPicture(first);
        // A PSD, an SVG or several pictures: a layered character (an SVG with fewer than
        // two top-level groups is a picture).
        status.info(`reading ${files.length > 1 ? `${files.length} pictures` : first.name}…`);
        void characters.openFiles(files).then((ok) => (characterOpened(ok) === "not-layered" ? openPicture(first) : undefined));
      },
      setDensity: (n) => theApp.setDensity(n),
      setMethod: (m) => {
        characters.setMethod(m);
        return theApp.setMethod(m);
      },
      setPinKind: (kind) => (theApp.board.pinKind = kind),
      setTool: (tool) => theApp.board.setTool(tool),
      setAmount: (kind, value) => (theApp.board.amounts[kind] = value),
      clearRegions: () => theApp.board.clearRegions(),
      showWireframe: (on) => theApp.showWireframe(on),
      showSimulation: (on) => theApp.showSimulation(on),
      showPins: (on) => {
        theApp.showPins(on);
        characters.setShowPins(on);
      },
      resetPose: () => (characters.active ? characters.resetPose() : theApp.resetPose()),
      exportPNG: (overlays) => {
        if (characters.active) {
          const name = characters.name?.replace(/\.[^.]*$/, "") ?? "character";
          characters.exportPNG().then((blob) => download(blob, `${name}-posed.png`), (e) => status.error(e));
          return;
        }
        const name = theApp.current?.picture.name.replace(/\.[^.]*$/, "") ?? "bunraku";
        theApp.exportPNG(overlays).then((blob) => download(blob, `${name}-posed.png`), (e) => status.error(e));
      },
    },
  );
  theApp.onDetailChange = (vertices) => controls.showDetail(vertices);
  const baseName = () => theApp.current?.picture.name.replace(/\.[^.]*$/, "") ?? "bunraku";
  const refresh = attachAnimation(
    {
      savePose: element("save-pose", HTMLButtonElement),
      poseList: element("pose-list", HTMLOListElement),
      blendField: element("blend-field", HTMLElement),
      blend: element("blend", HTMLInputElement),
      blendValue: element("blend-value", HTMLOutputElement),
      blendPad: element("blend-pad", HTMLCanvasElement),
      record: element("record", HTMLButtonElement),
      play: element("play", HTMLButtonElement),
      loop: element("loop", HTMLInputElement),
      saveDoc: element("save-doc", HTMLButtonElement),
      openDoc: element("open-doc", HTMLInputElement),
      exportVideo: element("export-video", HTMLButtonElement),
    },
    {
      savePose: () => void theApp.savePose(),
      removePose: (k) => void theApp.removePose(k),
      blend: (weights) => theApp.blend(weights),
      setRecording: (on) => void theApp.setRecording(on),
      play: () => void theApp.play(),
      setLoop: (on) => (theApp.loop = on),
      saveDocument: () =>
        void theApp.documentJSON().then((text) => {
          if (text !== null) download(new Blob([text], { type: "application/json" }), `${baseName()}.bunraku.json`);
        }),
      openDocument: (file) =>
        void file.text().then(
          (text) => theApp.openDocument(text, file.name).then((ok) => ok && characters.close()),
          (e: unknown) => status.error(e),
        ),
      exportVideo: () =>
        void theApp.exportVideo().then((video) => {
          if (!video) return status.info("nothing to export: record a drag first");
          if (video.kind === "webm") download(video.blob, `${baseName()}.webm`);
          else video.frames.forEach((frame, k) => download(frame, `${baseName()}-${String(k).padStart(4, "0")}.png`));
        }, (e: unknown) => status.error(e)),
    },
  );
  theApp.onAnimationChange = () => refresh({ poseCount: theApp.poses.length, recording: theApp.recording, playing: theApp.playing, loop: theApp.loop });
  theApp.onAnimationChange();
  const renderParameters = attachParameterPanel(
    {
      form: element("parameter-form", HTMLFormElement),
      id: element("parameter-id", HTMLInputElement),
      min: element("parameter-min", HTMLInputElement),
      max: element("parameter-max", HTMLInputElement),
      defaultValue: element("parameter-default", HTMLInputElement),
      keys: element("parameter-keys", HTMLInputElement),
      list: element("parameter-list", HTMLOListElement),
      padX: element("pad-x", HTMLSelectElement),
      padY: element("pad-y", HTMLSelectElement),
      pad: element("parameter-pad", HTMLCanvasElement),
      corrective: element("set-corrective", HTMLButtonElement),
    },
    // A layered character's own parameters while one is shown (characterparameters.ts).
    () => (characters.active ? characters.motion.parameters : theApp.parameters),
  );
  characters.motion.onParametersChange = () => renderParameters();
  // The timeline's key tracks and the curve editor's easings are the package's, on this
  // thread: its wasm module loads beside the worker's (not waited for: nothing uses it
  // before the user keys a value or opens a document).
  loadWasm().catch((e: unknown) => status.error(e, "the timeline cannot key values"));
  const timeline = new Timeline(
    {
      play: element("timeline-play", HTMLButtonElement),
      time: element("timeline-time", HTMLOutputElement),
      duration: element("timeline-duration", HTMLInputElement),
      strip: element("timeline", HTMLCanvasElement),
      parameter: element("timeline-parameter", HTMLSelectElement),
      key: element("timeline-key", HTMLButtonElement),
      remove: element("timeline-delete", HTMLButtonElement),
      ease: element("timeline-ease", HTMLSelectElement),
      curve: element("curve", HTMLCanvasElement),
    },
    theApp.parameters,
    {
      play: (from) => void theApp.playFrom(from),
      stop: () => theApp.endPlayback(),
      seek: (t) => {
        if (timeline.channels().length > 0) void theApp.seek(t);
      },
      playing: () => theApp.playing,
      changed: () => void syncMotion(),
    },
  );
  const swings = new Swings(
    {
      frequency: element("swing-frequency", HTMLInputElement),
      damping: element("swing-damping", HTMLInputElement),
      inertia: element("swing-inertia", HTMLInputElement),
      gravity: element("swing-gravity", HTMLInputElement),
      limit: element("swing-limit", HTMLInputElement),
      mix: element("swing-mix", HTMLInputElement),
      swingPin: element("swing-pin", HTMLButtonElement),
      parameter: element("swing-parameter", HTMLSelectElement),
      input: element("swing-input", HTMLSelectElement),
      addParameter: element("swing-parameter-add", HTMLButtonElement),
      list: element("swing-list", HTMLOListElement),
    },
    {
      rig: () => theApp.current?.rig ?? null,
      selectedPin: () => theApp.board.selected,
      parameters: theApp.parameters,
      changed: () => void syncMotion(),
      say: (text) => status.info(text),
    },
  );
  /** The springs' tick: an opened document's, else 120 Hz. */
  let tick = 120;
  const syncMotion = () => theApp.setMotion(timeline.channels(), swings.forWorker(theApp.current?.rig ?? null), timeline.duration, tick);
  // A new pin set: the pin springs are made again for it.
  theApp.board.pinsCompiled = () => {
    if (!swings.swingsPins) return;
    void syncMotion();
    swings.render();
  };
  theApp.onMotionChange = () => {
    renderParameters();
    timeline.parametersChanged();
    swings.render();
  };
  theApp.onMotionRestored = (state) => {
    tick = state?.tick ?? 120;
    timeline.restore(state?.channels ?? null, state?.duration ?? null);
    swings.restore(state?.swings ?? null, theApp.current?.rig ?? null);
  };
  theApp.onPlayFrame = (t) => {
    timeline.showTime(t);
    renderParameters();
  };
  const animationChanged = theApp.onAnimationChange;
  theApp.onAnimationChange = () => {
    animationChanged();
    timeline.render();
  };
  theApp.onMotionChange();
  // The test hook is compiled into the test build only (www/build.mjs defines __TEST__).
  if (__TEST__) exposeHook(theApp, stage, renderer.name, worker, overlay, characters, timeline, swings);
  await theApp.openPicture(firstPicture, DEFAULT_PUPPET.pins);
}

const status = new Status({
  pins: element("pin-count", HTMLElement),
  mesh: element("mesh-info", HTMLElement),
  flips: element("flip-count", HTMLElement),
  solve: element("solve-time", HTMLElement),
  fps: element("fps", HTMLElement),
  renderer: element("renderer-name", HTMLElement),
  message: element("message", HTMLElement),
});
// Whatever escapes a handler is shown on the page, not left as an uncaught exception.
window.addEventListener("error", (e) => status.error(e.error ?? e.message));
window.addEventListener("unhandledrejection", (e) => {
  e.preventDefault();
  status.error(e.reason);
});
main(status).catch((e: unknown) => status.error(e, "the demo could not start"));
