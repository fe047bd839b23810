// Puppet documents (docs/puppet-document.md): the puppet on screen saved as one (the
// picture by its URL, or embedded when it is the user's own), and a document opened as a
// new generation of the puppet, with its poses and its loop setting, and played.

import type { AppContext } from "./context.js";
import type { Opening, Wording } from "./opening.js";
import { pictureDataURL, pictureFromURL, type Picture } from "./picture.js";
import type { Playback } from "./playback.js";
import type { Poses } from "./poses.js";
import type { DocumentData, MotionState, OpenResult } from "./protocol.js";
import { newVersion } from "./rig.js";

/** What documents need besides the app's context. */
export interface DocumentParts {
  readonly opening: Opening;
  readonly poses: Poses;
  readonly playback: Playback;
  /** Puts a generation the worker opened on screen (it is the newest asked for). */
  readonly install: (picture: Picture, opened: OpenResult, wording: Wording) => void;
  /** Told when the poses change. */
  readonly changed: () => void;
  /** Gives the panels an opened document's parameters, channels and swings. */
  readonly restoreMotion: (state: MotionState) => void;
}

export class Documents {
  constructor(
    private readonly app: AppContext,
    private readonly parts: DocumentParts,
  ) {}

  /** The puppet as a document (docs/puppet-document.md): the picture by its URL, or
   *  embedded as a data URL when it is the user's own. */
  async save(): Promise<string | null> {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return null;
    const { pixels, url } = rig.picture;
    const picture = { url: url && !url.startsWith("blob:") ? url : pictureDataURL(rig.picture), width: pixels.width, height: pixels.height };
    this.app.settling.begin();
    const answer = await this.app.worker.call("document", { generation: rig.generation, picture, loop: this.parts.playback.loop });
    this.app.settling.end();
    this.app.settling.check();
    if (answer.status !== "ok") {
      if (answer.status === "error") this.app.status.error(answer.error, "could not save the document");
      return null;
    }
    if (answer.result.note) this.app.status.info(answer.result.note);
    return JSON.stringify(answer.result.document);
  }

  /** Opens a puppet document (its JSON text) and plays it. Resolves to whether it opened. */
  async open(text: string, name: string): Promise<boolean> {
    const { opening, poses, playback } = this.parts;
    const generation = opening.next();
    this.app.settling.begin();
    try {
      let doc: DocumentData;
      try {
        doc = JSON.parse(text) as DocumentData;
      } catch (e) {
        this.app.status.error(e, `${name} is not JSON`);
        return false;
      }
      const pictureField = doc.picture as { url?: unknown } | undefined;
      if (typeof pictureField?.url !== "string") {
        this.app.status.error(`${name} has no picture (picture.url)`);
        return false;
      }
      this.app.status.info(`opening ${name}…`);
      let picture: Picture;
      try {
        const url = pictureField.url;
        // The document's own URL is kept (a relative one stays relative when saved again).
        picture = { ...(await pictureFromURL(new URL(url, location.href), name.replace(/\.bunraku\.json$|\.json$/, ""))), url };
      } catch (e) {
        if (opening.isNewest(generation)) this.app.status.error(e, name);
        return false;
      }
      if (!opening.isNewest(generation)) return false;
      const answer = await this.app.worker.call("loadDocument", { generation, text, version: newVersion() });
      if (!opening.isNewest(generation)) {
        if (answer.status === "ok") opening.release(generation);
        return false;
      }
      if (answer.status !== "ok") {
        if (answer.status !== "dropped") this.app.status.error(answer.error, name);
        return false;
      }
      playback.loop = answer.result.loop;
      this.parts.install(picture, answer.result.opened, { refitted: `${name}: its pins do not fit; pinned automatically` });
      poses.replace(answer.result.poses);
      this.parts.restoreMotion(answer.result.motion);
      this.parts.changed();
    } finally {
      this.app.settling.end();
      this.app.settling.check();
    }
    void playback.play();
    return true;
  }
}
