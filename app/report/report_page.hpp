// The static parts of the review report page (report.cpp writes the markup around them): the
// stylesheet and the script, inlined into every page. Plain CSS and plain JS, no framework; nothing
// here may fetch anything (the page carries a Content-Security-Policy that forbids it anyway).
//
// Markup contract (report.cpp): every frame card with images holds a .viewer with four .view panels
// (data-view side | slider | blink | heat) and .tab buttons; a .stage is a box of --w x --h image
// pixels scaled by --zoom, with its images (.layer) absolutely positioned in it and sized in cqw
// (the stage is a size container), so every layer, the slider's .clip and the cluster <svg> scale
// together. Only the side-by-side images carry the data: URI; the others copy it (data-same=id).
#pragma once

namespace simreel::report_page {

inline constexpr const char* kCss = R"css(
:root {
  --bg: #f4f5f7; --panel: #fff; --text: #1c2230; --muted: #5a6373; --line: #d7dce3; --soft: #eef0f4;
  --fail: #b42318; --fail-bg: #fdecea; --pass: #1a7336; --pass-bg: #e3f4e8;
  --new: #1d5bbf; --new-bg: #e5eefb; --updated: #6940b0; --updated-bg: #efe9f9;
  --missing: #8f5300; --missing-bg: #fcf0d9;
  --zoom: 1;
}
* { box-sizing: border-box; }
[hidden] { display: none !important; }
html { background: var(--bg); }
body {
  margin: 0; color: var(--text);
  font: 14px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "Noto Sans", "Liberation Sans",
        "Helvetica Neue", Arial, sans-serif;
}
code, kbd, .mono {
  font-family: ui-monospace, SFMono-Regular, "SF Mono", Menlo, Consolas, "DejaVu Sans Mono",
               "Liberation Mono", monospace;
  font-size: 12.5px;
}
kbd {
  display: inline-block; min-width: 1.5em; padding: 0 4px; text-align: center; border-radius: 4px;
  border: 1px solid var(--line); border-bottom-width: 2px; background: var(--panel); color: var(--muted);
  line-height: 1.4; font-size: 11px;
}
a { color: var(--new); text-decoration: none; }
a:hover { text-decoration: underline; }
.page { max-width: 1400px; margin: 0 auto; padding: 0 24px; }
main.page { padding-bottom: 48px; }

/* header */
.top { background: var(--panel); border-bottom: 1px solid var(--line); }
.top .page { padding-top: 18px; padding-bottom: 16px; }
h1 { font-size: 13px; font-weight: 600; margin: 0; color: var(--muted); letter-spacing: .02em; }
.summary { font-size: 20px; font-weight: 600; margin: 2px 0 10px; }
.counts { display: flex; flex-wrap: wrap; gap: 6px; margin: 0 0 14px; }
.cmd { display: grid; grid-template-columns: max-content minmax(0, 1fr) max-content; gap: 6px 12px;
       align-items: center; }
.cmd .label { color: var(--muted); font-size: 12px; }
.cmd code { display: block; background: var(--soft); border: 1px solid var(--line); border-radius: 6px;
            padding: 5px 10px; white-space: pre-wrap; word-break: break-all; }
.fp-note { margin: 12px 0 0; font-size: 13px; color: var(--missing); }
.fp-note a { color: inherit; text-decoration: underline; }
.jump { margin-top: 12px; font-size: 13px; color: var(--muted); }
.jump a { margin-right: 12px; white-space: nowrap; }

/* controls */
button {
  font: inherit; font-size: 13px; color: var(--text); background: var(--panel); cursor: pointer;
  border: 1px solid var(--line); border-radius: 6px; padding: 3px 10px;
}
button:hover { background: var(--soft); }
button:focus-visible, input:focus-visible { outline: 2px solid var(--new); outline-offset: 1px; }
.seg { display: inline-flex; }
.seg button { border-radius: 0; margin-left: -1px; }
.seg button:first-child { border-radius: 6px 0 0 6px; margin-left: 0; }
.seg button:last-child { border-radius: 0 6px 6px 0; }
.seg button[aria-pressed="true"], .seg button[aria-selected="true"] {
  background: var(--text); border-color: var(--text); color: #fff; position: relative;
}
.seg button[aria-pressed="true"] kbd, .seg button[aria-selected="true"] kbd {
  background: transparent; color: #fff; border-color: rgba(255,255,255,.5);
}
.toolbar { position: sticky; top: 0; z-index: 10; background: rgba(244,245,247,.96);
           border-bottom: 1px solid var(--line); }
.toolbar .page { display: flex; flex-wrap: wrap; align-items: center; gap: 8px 20px;
                 padding-top: 8px; padding-bottom: 8px; }
.toolbar .group { display: flex; align-items: center; gap: 8px; }
.toolbar .name { color: var(--muted); font-size: 12px; }
.toolbar label { font-size: 13px; display: flex; align-items: center; gap: 4px; }

/* status */
.badge {
  display: inline-block; padding: 1px 10px; border-radius: 999px; font-size: 11.5px; font-weight: 700;
  letter-spacing: .05em; text-transform: uppercase; white-space: nowrap; border: 1px solid;
}
.badge.st-fail { color: var(--fail); background: var(--fail-bg); }
.badge.st-pass { color: var(--pass); background: var(--pass-bg); }
.badge.st-new { color: var(--new); background: var(--new-bg); }
.badge.st-updated { color: var(--updated); background: var(--updated-bg); }
.badge.st-missing { color: var(--missing); background: var(--missing-bg); }

/* sections and cards */
h2 { font-size: 15px; margin: 26px 0 10px; }
h2 .n, summary .n { color: var(--muted); font-weight: 400; }
details.group > summary { cursor: pointer; font-size: 15px; font-weight: 700; margin: 26px 0 10px; }
.panel, .card { background: var(--panel); border: 1px solid var(--line); border-radius: 8px; }
h2, .card { scroll-margin-top: 56px; }  /* anchors land below the sticky toolbar */
.card { border-left: 4px solid var(--line); padding: 12px 16px 14px; margin: 0 0 14px; }
.card.st-fail { border-left-color: var(--fail); }
.card.st-pass { border-left-color: var(--pass); }
.card.st-new { border-left-color: var(--new); }
.card.st-updated { border-left-color: var(--updated); }
.card.st-missing { border-left-color: var(--missing); }
.card-head { display: flex; align-items: center; gap: 12px; }
.card-head h3 { font-size: 15px; margin: 0; overflow-wrap: anywhere; }
.card-head .meta { color: var(--muted); font-size: 13px; font-variant-numeric: tabular-nums; }
.card-head .badge { margin-left: auto; }
.note { margin: 8px 0 0; color: var(--muted); font-size: 13px; }
.attrib { margin: 10px 0 0; padding: 8px 12px; border-radius: 6px; border: 1px solid var(--line);
          background: var(--soft); }
.attrib strong { font-size: 13.5px; }
.attrib .why { color: var(--muted); font-size: 13px; margin-left: 6px; }
.attrib.k-physics { background: #fff5e6; border-color: #f0d2a3; }
.attrib.k-rendering { background: #eaf1fc; border-color: #bfd3f2; }
.attrib.k-size, .attrib.k-count { background: #f2edfb; border-color: #d5c7f0; }
.attrib.k-pixels { background: #eaf1fc; border-color: #bfd3f2; }
.attrib ul { margin: 4px 0 0; padding-left: 18px; }
.attrib li { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, "DejaVu Sans Mono", monospace;
             font-size: 12.5px; overflow-wrap: anywhere; }
table.metrics { border-collapse: collapse; margin: 12px 0 4px; }
table.metrics th { text-align: left; font-size: 11.5px; font-weight: 500; color: var(--muted);
                   padding: 0 28px 0 0; white-space: nowrap; }
table.metrics td { font-size: 15px; font-variant-numeric: tabular-nums; padding: 0 28px 0 0;
                   white-space: nowrap; }

/* viewer */
.viewer { margin-top: 12px; }
.viewer .tabs { margin-bottom: 10px; }
.view { overflow: auto; }
.sbs { display: flex; gap: 12px; align-items: flex-start; }
.sbs figure { margin: 0; flex: 1 1 0; min-width: 0; }
.zoomed .sbs figure { flex: none; }
figcaption, .caption { font-size: 12px; color: var(--muted); margin: 0 0 4px; }
.caption { margin: 6px 0 0; display: flex; align-items: center; gap: 12px; flex-wrap: wrap; }
.stage {
  position: relative; overflow: hidden; container-type: inline-size; background: #dfe3e8;
  width: calc(var(--w) * var(--zoom) * 1px); aspect-ratio: var(--w) / var(--h);
  box-shadow: 0 0 0 1px var(--line);
}
.fit .stage, .fit .range, .fit .noimg { max-width: 100%; }
.layer { position: absolute; left: 0; top: 0; display: block; height: auto; max-width: none;
         user-select: none; -webkit-user-drag: none; }
.pixelated .layer { image-rendering: pixelated; }
.clip { position: absolute; left: 0; top: 0; bottom: 0; width: 50%; overflow: hidden; }
.divider { position: absolute; top: 0; bottom: 0; left: 50%; width: 2px; margin-left: -1px;
           background: #fff; box-shadow: 0 0 0 1px rgba(0,0,0,.5); pointer-events: none; }
.slider-stage { cursor: ew-resize; touch-action: none; }
.range { display: block; width: calc(var(--w) * var(--zoom) * 1px); margin: 6px 0 0; }
.blink-stage.show-expected .layer.actual { visibility: hidden; }
.blink-label { font-weight: 600; color: var(--text); min-width: 9em; }
.boxes { position: absolute; left: 0; top: 0; width: 100%; height: 100%; overflow: visible; }
.boxes rect { fill: transparent; stroke: #00b7ff; stroke-width: 2px; vector-effect: non-scaling-stroke; }
.legend { display: flex; flex-wrap: wrap; gap: 16px; }
.sw { display: inline-block; width: 10px; height: 10px; border-radius: 2px; margin-right: 5px;
      vertical-align: -1px; }
.noimg {
  display: flex; align-items: center; justify-content: center; text-align: center; padding: 12px;
  width: calc(var(--w) * var(--zoom) * 1px); aspect-ratio: var(--w) / var(--h); min-height: 60px;
  color: var(--muted); font-size: 13px; border: 1px dashed var(--line); border-radius: 4px;
  background: repeating-linear-gradient(45deg, #f3f4f7 0 8px, #eceef2 8px 16px);
}

/* fingerprints */
.fp { padding: 4px 0 0; overflow: auto; }
.fp table { border-collapse: collapse; width: 100%; font-size: 13px; }
.fp th, .fp td { text-align: left; padding: 5px 14px; border-top: 1px solid var(--soft);
                 vertical-align: top; overflow-wrap: anywhere; }
.fp thead th { border-top: 0; font-size: 12px; color: var(--muted); font-weight: 500; }
.fp tbody th { font-weight: 500; white-space: nowrap; width: 1%; }
.fp td { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, "DejaVu Sans Mono", monospace;
         font-size: 12.5px; width: 45%; }
.fp tr.differ th, .fp tr.differ td { background: #fff5e6; }
.fp tr.differ th::before { content: "\2260"; color: var(--missing); font-weight: 700; margin-right: 6px; }
.fp .absent { color: var(--muted); font-style: italic; font-family: inherit; }
.empty { color: var(--muted); padding: 14px 16px; margin: 0; }

.selftest { background: #1c2230; color: #fff; padding: 8px 24px; font-family: ui-monospace, monospace; }
)css";

inline constexpr const char* kJs = R"js(
(function () {
  'use strict';
  var errors = [];
  window.addEventListener('error', function (e) { errors.push(e.message || String(e)); });

  var VIEWS = ['side', 'slider', 'blink', 'heat'];
  var root = document.documentElement;
  var viewers = [].slice.call(document.querySelectorAll('.viewer'));
  function all(sel, ctx) { return [].slice.call((ctx || document).querySelectorAll(sel)); }

  // Each image is embedded once (in the side-by-side view); the other views copy its data: URI.
  all('img[data-same]').forEach(function (img) {
    img.src = document.getElementById(img.getAttribute('data-same')).src;
  });

  function press(sel, attr, value) {
    all(sel).forEach(function (b) { b.setAttribute('aria-pressed', String(b.getAttribute(attr) === value)); });
  }
  function setView(v, name) {
    v.setAttribute('data-view', name);
    all('.tab', v).forEach(function (t) {
      t.setAttribute('aria-selected', String(t.getAttribute('data-view') === name));
    });
    all('.view', v).forEach(function (p) { p.hidden = p.getAttribute('data-view') !== name; });
  }
  function setAllViews(name) {
    viewers.forEach(function (v) { setView(v, name); });
    press('[data-allview]', 'data-allview', name);
  }

  // Slider: the actual image, clipped to the left pct % of the stage, over the expected one.
  function setSlider(v, pct) {
    pct = Math.max(0, Math.min(100, pct));
    var clip = v.querySelector('.clip');
    if (!clip) return;
    clip.style.width = pct + '%';
    v.querySelector('.divider').style.left = pct + '%';
    var range = v.querySelector('.range');
    if (+range.value !== pct) range.value = pct;
  }

  // Blink: the actual image over the expected one, hidden every other tick (or by Flip).
  function showBlink(v, expected) {
    var s = v.querySelector('.blink-stage');
    if (!s) return;
    s.classList.toggle('show-expected', expected);
    var l = v.querySelector('.blink-label');
    l.textContent = l.getAttribute(expected ? 'data-expected' : 'data-actual');
    v.setAttribute('data-flips', String(+v.getAttribute('data-flips') + 1));
  }
  function flip(v) {
    var s = v.querySelector('.blink-stage');
    if (s) showBlink(v, !s.classList.contains('show-expected'));
  }
  setInterval(function () {
    viewers.forEach(function (v) {
      var auto = v.querySelector('.blink-auto');
      if (v.getAttribute('data-view') === 'blink' && auto && auto.checked) flip(v);
    });
  }, 500);

  // Zoom: 'fit' (1 image pixel = 1 CSS pixel, shrunk to the card) or exactly 1, 2, 4 CSS px.
  function setPixelated(on) {
    root.classList.toggle('pixelated', on);
    document.getElementById('pixelated').checked = on;
  }
  function setZoom(z) {
    root.classList.toggle('fit', z === 'fit');
    root.classList.toggle('zoomed', z !== 'fit');
    root.style.setProperty('--zoom', z === 'fit' ? '1' : z);
    setPixelated(z !== 'fit');
    press('[data-zoom]', 'data-zoom', z);
  }

  function copy(b) {
    var el = document.getElementById(b.getAttribute('data-copy'));
    function done(ok) {
      b.textContent = ok ? 'Copied' : 'Press Ctrl+C';
      setTimeout(function () { b.textContent = 'Copy'; }, 1500);
    }
    function bySelection() {  // older browsers, or no clipboard permission: leaves the text selected
      var r = document.createRange();
      r.selectNodeContents(el);
      getSelection().removeAllRanges();
      getSelection().addRange(r);
      try { return document.execCommand('copy'); } catch (x) { return false; }
    }
    if (navigator.clipboard && navigator.clipboard.writeText) {
      navigator.clipboard.writeText(el.textContent).then(function () { done(true); },
                                                          function () { done(bySelection()); });
    } else {
      done(bySelection());
    }
  }

  document.addEventListener('click', function (e) {
    var b = e.target.closest('button');
    if (!b) return;
    var v = b.closest('.viewer');
    if (b.classList.contains('tab')) setView(v, b.getAttribute('data-view'));
    else if (b.hasAttribute('data-allview')) setAllViews(b.getAttribute('data-allview'));
    else if (b.hasAttribute('data-zoom')) setZoom(b.getAttribute('data-zoom'));
    else if (b.classList.contains('flip')) { v.querySelector('.blink-auto').checked = false; flip(v); }
    else if (b.hasAttribute('data-copy')) copy(b);
  });
  document.addEventListener('input', function (e) {
    if (e.target.classList.contains('range')) setSlider(e.target.closest('.viewer'), +e.target.value);
  });
  document.addEventListener('change', function (e) {
    if (e.target.id === 'pixelated') setPixelated(e.target.checked);
  });
  document.addEventListener('pointerdown', function (e) {  // drag the divider anywhere on the image
    var s = e.target.closest('.slider-stage');
    if (!s) return;
    var v = s.closest('.viewer');
    function move(ev) {
      var r = s.getBoundingClientRect();
      setSlider(v, Math.round((ev.clientX - r.left) / r.width * 1000) / 10);
    }
    function up() {
      s.removeEventListener('pointermove', move);
      s.removeEventListener('pointerup', up);
      s.removeEventListener('pointercancel', up);
    }
    e.preventDefault();
    try { s.setPointerCapture(e.pointerId); } catch (x) { /* synthetic events have no pointer */ }
    move(e);
    s.addEventListener('pointermove', move);
    s.addEventListener('pointerup', up);
    s.addEventListener('pointercancel', up);
  });
  document.addEventListener('keydown', function (e) {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    var t = e.target;
    if (t && (t.tagName === 'TEXTAREA' || (t.tagName === 'INPUT' && t.type === 'text'))) return;
    var i = ['1', '2', '3', '4'].indexOf(e.key);
    if (i >= 0) { setAllViews(VIEWS[i]); e.preventDefault(); }
  });

  setAllViews('side');
  setZoom('fit');
  viewers.forEach(function (v) { setSlider(v, 50); showBlink(v, true); v.setAttribute('data-flips', '0'); });

  if (location.hash === '#selftest') selftest();

  // ---- self-test: drives the page the way a user does and reports into #selftest-result. Run by
  // tests/app/report/report_test.cpp in headless Chromium (--dump-dom, virtual time for the timers).
  function selftest() {
    var out = document.getElementById('selftest-result');
    out.hidden = false;
    out.textContent = 'SELFTEST RUNNING';
    var checks = 0;
    function check(ok, what) { checks++; if (!ok) throw new Error(what); }
    function near(a, b, tol) { return Math.abs(a - b) <= tol; }
    function wait(ms) { return new Promise(function (r) { setTimeout(r, ms); }); }
    function shown(el) {
      return !!el && getComputedStyle(el).display !== 'none' && el.getBoundingClientRect().width > 0;
    }
    function key(k) { document.body.dispatchEvent(new KeyboardEvent('keydown', { key: k, bubbles: true })); }
    function click(el) { el.dispatchEvent(new MouseEvent('click', { bubbles: true })); }
    function loaded(img) { return img.complete && img.naturalWidth > 0; }
    function name(v) { return v.closest('.card').id; }
    function expectView(v, view) {
      all('.view', v).forEach(function (p) {
        var want = p.getAttribute('data-view') === view;
        check(shown(p) === want, name(v) + ': view ' + p.getAttribute('data-view') +
                                 (want ? ' not shown' : ' shown') + ' in ' + view);
      });
      var tab = v.querySelector('.tab[aria-selected="true"]');
      check(tab && tab.getAttribute('data-view') === view, name(v) + ': tab not selected for ' + view);
    }
    function checkHeat(v) {
      var img = v.querySelector('.view[data-view="heat"] img.layer');
      var svg = v.querySelector('.view[data-view="heat"] svg.boxes');
      if (!img || !svg) return;
      var ir = img.getBoundingClientRect(), sr = svg.getBoundingClientRect();
      check(near(ir.left, sr.left, 1) && near(ir.top, sr.top, 1) && near(ir.width, sr.width, 1) &&
            near(ir.height, sr.height, 1), name(v) + ': cluster overlay does not cover the heat map');
      var rects = svg.querySelectorAll('rect');
      check(rects.length === +svg.getAttribute('data-clusters'), name(v) + ': cluster boxes missing');
      if (!rects.length) return;
      var k = ir.width / img.naturalWidth, rr = rects[0].getBoundingClientRect();
      check(near(rr.left - ir.left, rects[0].x.baseVal.value * k, 2) &&
            near(rr.width, rects[0].width.baseVal.value * k, 2), name(v) + ': cluster box not scaled');
    }

    async function run() {
      all('details').forEach(function (d) { d.open = true; });  // lay out the passing frames too
      var imgs = all('img');
      check(imgs.length > 0, 'no images');
      for (var t = 0; t < 60 && !imgs.every(loaded); t++) await wait(50);
      imgs.forEach(function (img) {
        check(loaded(img), 'image not loaded: ' + (img.id || img.getAttribute('data-same')));
        check(img.naturalWidth === +img.getAttribute('data-w') &&
              img.naturalHeight === +img.getAttribute('data-h'), 'wrong image size: ' + img.alt);
      });
      check(viewers.length > 0, 'no viewers');

      // Views by key, for every card at once, then by one card's tabs (only that card changes).
      ['4', '3', '2', '1'].forEach(function (k) {
        key(k);
        viewers.forEach(function (v) { expectView(v, VIEWS[+k - 1]); });
      });
      var v0 = viewers[0];
      VIEWS.forEach(function (view) {
        click(v0.querySelector('.tab[data-view="' + view + '"]'));
        expectView(v0, view);
        if (viewers[1]) expectView(viewers[1], 'side');
      });
      click(document.querySelector('[data-allview="heat"]'));
      viewers.forEach(function (v) { expectView(v, 'heat'); checkHeat(v); });

      // Slider: drag to 70 %, then the range to 30 %; the clipped top image keeps its full size.
      key('2');
      viewers.forEach(function (v) {
        var s = v.querySelector('.slider-stage');
        if (!s) return;
        var clip = v.querySelector('.clip'), range = v.querySelector('.range');
        check(clip && range && clip.querySelector('img'), name(v) + ': slider parts missing');
        var r = s.getBoundingClientRect(), k = r.width / +getComputedStyle(s).getPropertyValue('--w');
        check(near(clip.getBoundingClientRect().width, 0.5 * r.width, 1.5), name(v) + ': slider not at 50%');
        s.dispatchEvent(new PointerEvent('pointerdown', { bubbles: true, pointerId: 1,
                                                          clientX: r.left + 0.7 * r.width, clientY: r.top + 2 }));
        s.dispatchEvent(new PointerEvent('pointerup', { bubbles: true, pointerId: 1 }));
        check(near(clip.getBoundingClientRect().width, 0.7 * r.width, 1.5), name(v) + ': drag did not move the slider');
        range.value = '30';
        range.dispatchEvent(new Event('input', { bubbles: true }));
        check(near(clip.getBoundingClientRect().width, 0.3 * r.width, 1.5), name(v) + ': slider at 30% clips ' +
              clip.getBoundingClientRect().width + ' of ' + r.width + ' px');
        // Both images at the stage's scale, from its top left corner: the clip cuts, never squeezes.
        [clip.querySelector('img'), s.querySelector('.layer.expected')].forEach(function (img) {
          var b = img.getBoundingClientRect();
          check(near(b.left, r.left, 1) && near(b.top, r.top, 1) && near(b.width, img.naturalWidth * k, 1) &&
                near(b.height, img.naturalHeight * k, 1), name(v) + ': slider squeezes the ' + img.alt + ' image');
        });
        check(near(v.querySelector('.divider').getBoundingClientRect().left + 1 - r.left, 0.3 * r.width, 1.5),
              name(v) + ': divider not at 30%');
      });

      // Blink: alternates on its own, Flip flips and stops it.
      key('3');
      var blinkers = viewers.filter(function (v) { return v.querySelector('.blink-stage'); });
      var before = blinkers.map(function (v) { return +v.getAttribute('data-flips'); });
      await wait(1100);
      blinkers.forEach(function (v, i) {
        check(+v.getAttribute('data-flips') - before[i] >= 2, name(v) + ': blink does not alternate');
        var actual = v.querySelector('.blink-stage .layer.actual'), label = v.querySelector('.blink-label');
        var was = getComputedStyle(actual).visibility, text = label.textContent;
        click(v.querySelector('.flip'));
        check(getComputedStyle(actual).visibility !== was && label.textContent !== text,
              name(v) + ': Flip did not change the shown image');
        check(!v.querySelector('.blink-auto').checked, name(v) + ': Flip did not stop the blinking');
        before[i] = +v.getAttribute('data-flips');
      });
      await wait(700);
      blinkers.forEach(function (v, i) {
        check(+v.getAttribute('data-flips') === before[i], name(v) + ': blink runs after Flip');
      });

      // Zoom: 2x is exactly two CSS pixels per image pixel, pixelated, overlay still on the image.
      key('1');
      click(document.querySelector('[data-zoom="2"]'));
      var img = v0.querySelector('.view[data-view="side"] img.layer');
      check(near(img.getBoundingClientRect().width, 2 * img.naturalWidth, 0.5), 'zoom 2x: image is ' +
            img.getBoundingClientRect().width + ' px wide, natural ' + img.naturalWidth);
      check(getComputedStyle(img).imageRendering === 'pixelated', 'zoom 2x: not pixelated');
      key('4');
      viewers.forEach(checkHeat);
      click(document.querySelector('[data-zoom="fit"]'));
      check(getComputedStyle(img).imageRendering !== 'pixelated', 'fit: still pixelated');
      key('1');
      check(document.querySelector('[data-copy]') !== null, 'no copy button');
    }
    run().then(function () {
      out.textContent = errors.length ? 'SELFTEST FAIL: page error: ' + errors[0]
                                      : 'SELFTEST PASS (' + checks + ' checks)';
    }, function (e) {
      out.textContent = 'SELFTEST FAIL: ' + e.message;
    });
  }
})();
)js";

}  // namespace simreel::report_page
