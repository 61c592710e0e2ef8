// rapp: MathJax 2's `MathJax.Hub.Queue` for the ipywidgets HTML manager, on MathJax 3.
//
// The widget manager typesets a widget's label with MathJax.Hub.Queue(["Typeset", MathJax.Hub, el])
// whenever window.MathJax exists; MathJax 3 has no Hub, so every label threw "Cannot read
// properties of undefined (reading 'Queue')". Loaded before the manager and before MathJax (see
// book/_ext/reader_pages.py), this puts a Hub on whatever object window.MathJax is (Sphinx's
// configuration first, then MathJax 3 itself, which replaces it) and typesets the queued elements
// with MathJax 3's typesetPromise once MathJax has started.
(function () {
  "use strict";
  var pending = [];
  var flushing = null;

  function started() {
    var mj = current;
    return mj && mj.startup && mj.startup.promise && typeof mj.typesetPromise === "function";
  }

  function flush() {
    if (!started() || flushing || !pending.length) return;
    var items = pending.splice(0);
    flushing = current.startup.promise
      .then(function () {
        var els = items.filter(function (x) { return x && x.nodeType === 1 && x.isConnected; });
        return els.length ? current.typesetPromise(els) : null;
      })
      .then(function () {
        items.forEach(function (x) { if (typeof x === "function") x(); });
      })
      .catch(function (err) { console.warn("rapp: MathJax could not typeset a widget label", err); })
      .then(function () { flushing = null; flush(); });
  }

  var hub = {
    // Queue(["Typeset", MathJax.Hub, element], callback, ...): elements are typeset, functions
    // called afterwards; other MathJax 2 commands have no MathJax 3 counterpart and are skipped.
    Queue: function () {
      for (var i = 0; i < arguments.length; i++) {
        var a = arguments[i];
        if (Array.isArray(a) && a[0] === "Typeset") pending.push(a[2] || document.body);
        else if (typeof a === "function") pending.push(a);
      }
      flush();
    },
    Config: function () {},
    Register: { StartupHook: function () {}, MessageHook: function () {} },
  };

  function install(mj) {
    if (mj && typeof mj === "object" && !Object.prototype.hasOwnProperty.call(mj, "Hub")) {
      // Not enumerable: MathJax 3 reads its configuration's own keys and must not see this one.
      Object.defineProperty(mj, "Hub", { value: hub, configurable: true, enumerable: false });
    }
  }

  var current = window.MathJax;
  install(current);
  Object.defineProperty(window, "MathJax", {
    configurable: true,
    enumerable: true,
    get: function () { return current; },
    set: function (value) { current = value; install(value); setTimeout(flush, 0); },
  });
  window.addEventListener("load", flush);
})();
