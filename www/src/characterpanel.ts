// The demo's draw-order panel for a layered character (issue 24): the parts listed bottom
// first, each with buttons to send it back or bring it forward one place.

/** Fills `list` with the parts of `order` (bottom first); `move(name, step)` is called when
 *  a part's ▼ (−1) or ▲ (+1) button is pressed. */
export function renderOrderPanel(list: HTMLOListElement, order: readonly string[], move: (name: string, step: 1 | -1) => void): void {
  list.replaceChildren();
  order.forEach((name, k) => {
    const item = document.createElement("li");
    item.dataset.part = name;
    const label = document.createElement("span");
    label.textContent = name;
    const button = (text: string, className: string, title: string, disabled: boolean, step: 1 | -1) => {
      const b = document.createElement("button");
      b.type = "button";
      b.textContent = text;
      b.className = className;
      b.title = title;
      b.setAttribute("aria-label", title);
      b.disabled = disabled;
      b.addEventListener("click", () => move(name, step));
      return b;
    };
    item.append(
      label,
      button("▼", "part-back", `Send ${name} back`, k === 0, -1),
      button("▲", "part-forward", `Bring ${name} forward`, k === order.length - 1, 1),
    );
    list.append(item);
  });
}
