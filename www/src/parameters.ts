// The parameters of the picture on screen (issue 25): named values with keyforms, in a
// `Rig` that lives in the worker next to the puppet (motion.ts there). The page keeps their
// definitions, which keys have keyforms, the correctives, and each slider's value; a value
// change asks the worker for the rig's pose (`rig.setValue`, `rig.poseInto`), shown as a
// pose the puppet did not solve (solving.ts), as a blend is. At most one pose is in flight;
// the newest values go when it comes back. A keyform is the pose on screen.

import type { Answer } from "./client.js";
import type { AppContext } from "./context.js";
import type { CorrectiveInfo, MotionResult, ParameterInfo, ParameterSpec } from "./protocol.js";
import type { Solver } from "./solving.js";

export class Parameters {
  /** The rig's parameters (in order) and correctives, as the worker last answered. */
  private infos: readonly ParameterInfo[] = [];
  private correctiveList: readonly CorrectiveInfo[] = [];
  /** Each parameter's value on the page (the slider's). */
  private readonly valueOf = new Map<string, number>();
  private readonly posing = { due: false, inFlight: false };
  /** Counts the changes of the list (not of the values): the panel rebuilds on a new one. */
  revision = 0;

  /** `endPlayback` stops playback (a slider takes the pose over); `changed` is told when
   *  the parameters, keyforms or values change (the panel redraws). */
  constructor(
    private readonly app: AppContext,
    private readonly solver: Solver,
    private readonly endPlayback: () => void,
    private readonly changed: () => void,
  ) {}

  get list(): readonly ParameterInfo[] {
    return this.infos;
  }

  get correctives(): readonly CorrectiveInfo[] {
    return this.correctiveList;
  }

  /** Parameter `id`'s value on the page (its default before any change). */
  value(id: string): number {
    return this.valueOf.get(id) ?? this.infos.find((p) => p.id === id)?.default ?? 0;
  }

  /** Whether no pose is in flight or waiting. */
  idle(): boolean {
    return !this.posing.inFlight && !this.posing.due;
  }

  /** A new puppet is on screen: its parameters (none for a picture, an opened document's). */
  replace(state: { parameters: readonly ParameterInfo[]; correctives: readonly CorrectiveInfo[] } | null): void {
    this.infos = state?.parameters ?? [];
    this.correctiveList = state?.correctives ?? [];
    this.revision++;
    this.valueOf.clear();
    this.changed();
  }

  /** Adds a parameter (at its default value); resolves to whether the rig took it (its
   *  error, with the field it names, is shown). */
  add(spec: ParameterSpec): Promise<boolean> {
    return this.ask("the parameter was not added", (generation) => this.app.worker.call("addParameter", { generation, parameter: spec }));
  }

  remove(id: string): Promise<boolean> {
    return this.ask("the parameter was not removed", (generation) => this.app.worker.call("removeParameter", { generation, id }));
  }

  /** Makes the pose on screen parameter `id`'s keyform at `key` (null: clears it). */
  setKeyform(id: string, key: number, clear = false): Promise<boolean> {
    const positions = clear ? null : (this.app.rig?.positions.slice() ?? null);
    if (!clear && !positions) return Promise.resolve(false);
    return this.ask("the keyform was not set", (generation) => this.app.worker.call("setKeyform", { generation, id, key, positions }));
  }

  /** Makes the pose on screen the corrective at keys `at` of parameters `ids`. */
  setCorrective(ids: readonly [string, string], at: readonly [number, number], clear = false): Promise<boolean> {
    const positions = clear ? null : (this.app.rig?.positions.slice() ?? null);
    return this.ask("the corrective was not set", (generation) => this.app.worker.call("setCorrective", { generation, ids, at, positions }));
  }

  /** Sets parameter `id`'s value (clamped to its range) and shows the rig's pose. */
  setValue(id: string, value: number): void {
    const p = this.infos.find((q) => q.id === id);
    if (!p || !Number.isFinite(value)) return;
    this.valueOf.set(id, Math.min(p.max, Math.max(p.min, value)));
    this.endPlayback();
    this.posing.due = true;
    this.changed();
    this.pump();
  }

  /** Shows `value` on parameter `id`'s slider without posing (playback poses). */
  showValue(id: string, value: number): void {
    this.valueOf.set(id, value);
  }

  /** Every value back to its default. */
  resetValues(): void {
    this.valueOf.clear();
    this.changed();
  }

  private async ask(context: string, call: (generation: number) => Promise<Answer<"addParameter">>): Promise<boolean> {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return false;
    this.app.settling.begin();
    try {
      const answer = await call(rig.generation);
      if (rig !== this.app.rig) return false;
      if (answer.status !== "ok") {
        if (answer.status === "error") this.app.status.error(answer.error, context);
        return false;
      }
      this.take(answer.result);
      return true;
    } finally {
      this.app.settling.end();
      this.app.settling.check();
    }
  }

  private take(result: MotionResult): void {
    this.infos = result.parameters;
    this.correctiveList = result.correctives;
    this.revision++;
    for (const id of [...this.valueOf.keys()]) if (!this.infos.some((p) => p.id === id)) this.valueOf.delete(id);
    this.changed();
  }

  private pump(): void {
    const rig = this.app.rig;
    const p = this.posing;
    if (!p.due || p.inFlight || !rig || !this.app.live || this.infos.length === 0) return this.app.settling.check();
    p.due = false;
    p.inFlight = true;
    const values = Float64Array.from(this.infos, (q) => this.value(q.id));
    const sent = performance.now();
    void this.app.worker.call("parameterPose", { generation: rig.generation, values, out: new Float64Array(rig.rest.length) }).then((answer) => {
      p.inFlight = false;
      if (answer.status === "ok" && rig === this.app.rig) this.solver.showUnsolved(rig, answer.result.positions, answer.result.ms, sent);
      else if (answer.status === "error" && rig === this.app.rig) this.app.status.error(answer.error, "the parameters could not pose");
      this.pump();
    });
  }
}
