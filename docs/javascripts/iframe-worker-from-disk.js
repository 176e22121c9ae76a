/* A stand-in for Worker on pages opened from disk (file://), where browsers refuse to start a
   worker from a file. Material's search runs in a worker; its offline plugin (mkdocs.yml) loads
   the search index from a script and expects a shim like this one among `extra.polyfills`
   (without one it adds a copy fetched from unpkg.com, and this site fetches nothing from
   outside). The worker's script runs in a hidden iframe of the page instead, and the messages go
   both ways as to and from a worker: each one a structured clone, made in the realm that gets it.
   A page served over http(s) keeps the browser's own Worker. */
(function () {
  "use strict";
  if (location.protocol !== "file:") {
    return;
  }

  class FrameWorker extends EventTarget {
    constructor(url) {
      super();
      this.onmessage = null;
      this.onerror = null;
      this.pending = [];
      this.scope = null;
      this.frame = document.createElement("iframe");
      this.frame.hidden = true;
      this.frame.setAttribute("aria-hidden", "true");
      (document.body || document.documentElement).appendChild(this.frame);
      const scope = this.frame.contentWindow;
      // what the worker's script calls its answers with
      scope.postMessage = data => this.answer(structuredClone(data));
      scope.importScripts = (...urls) => {
        throw new Error(`importScripts(${urls.join(", ")}) is not available to a worker started from disk`);
      };
      const script = scope.document.createElement("script");
      script.src = new URL(url, location.href).href;
      script.onload = () => {
        this.scope = scope;
        this.pending.splice(0).forEach(data => this.postMessage(data));
      };
      script.onerror = () => this.fail(`the worker's script ${script.src} did not load`);
      scope.document.documentElement.appendChild(script);
    }

    postMessage(data) {
      if (this.scope === null) {
        this.pending.push(data);
        return;
      }
      this.scope.dispatchEvent(new this.scope.MessageEvent("message", {data: this.scope.structuredClone(data)}));
    }

    answer(data) {
      const event = new MessageEvent("message", {data});
      if (typeof this.onmessage === "function") {
        this.onmessage(event);
      }
      this.dispatchEvent(event);
    }

    fail(message) {
      const event = new ErrorEvent("error", {message});
      if (typeof this.onerror === "function") {
        this.onerror(event);
      }
      this.dispatchEvent(event);
    }

    terminate() {
      this.frame.remove();
      this.scope = null;
    }
  }

  window.Worker = FrameWorker;
})();
