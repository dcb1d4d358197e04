// The report's image comparison viewer (docs/compare-and-report.md, "The viewer"). The page holds
// every picture once, as plain figures grouped by method, which read as they are without a script;
// this script turns each `.viewer` into one view over them: methods and the reference switched in
// place (number keys, arrows, clicks), layers (shaded, V, errors) by key, the error map over the
// shaded image, and a nearest-neighbour zoom whose crop every method shares. It also makes the
// charts' points answer: hovering or focusing one shows its figures, clicking it opens the method.
// No network, no storage: it only reads the page.
(function () {
  'use strict';
  var ZOOMS = [2, 4, 8, 16, 32];
  var ZOOM_PX = 256; // the zoom panel's side in CSS pixels
  var STRIP_PX = 96; // each method's crop in the strip
  var LAYER_KEYS = { s: 'shaded', v: 'visibility', e: 'abs_error', d: 'signed_error' };
  var LAYER_NAMES = { shaded: 'shaded', visibility: 'V', abs_error: '|error|', signed_error: 'signed error' };
  var viewers = [];
  var active = null;

  function el(tag, cls, text) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function Viewer(root) {
    var self = this;
    this.root = root;
    this.items = Array.prototype.map.call(root.querySelectorAll(':scope > .v-item'), function (node) {
      var layers = {};
      var order = [];
      node.querySelectorAll('figure[data-layer]').forEach(function (f) {
        layers[f.dataset.layer] = { img: f.querySelector('img'), caption: f.querySelector('figcaption').textContent };
        order.push(f.dataset.layer);
      });
      var fig = node.querySelector('.v-figures');
      return { node: node, label: node.dataset.label, reference: node.hasAttribute('data-reference'), figures: fig ? fig.textContent : '', layers: layers, order: order };
    });
    this.layerNames = [];
    this.items.forEach(function (it) {
      it.order.forEach(function (l) { if (self.layerNames.indexOf(l) < 0) self.layerNames.push(l); });
    });
    // Number keys: 0 is the reference where there is one, the methods count from 1.
    this.base = this.items.length && this.items[0].reference ? 0 : 1;
    this.current = this.items.length > 1 && this.items[0].reference ? 1 : 0;
    this.layer = this.layerNames[0];
    this.overlay = false;
    this.zoom = 8;
    this.u = 0.5; // the crop's centre, as fractions of the image's width (both axes: legends hang below)
    this.v = 0.5;
    this.locked = false;
    this.canOverlay = this.items.some(function (it) { return it.layers.shaded && it.layers.abs_error; });
    // The zoom and the strip draw every method's picture, which decodes it: only once the viewer is
    // on screen, so a long page loads as fast as its text.
    this.visible = false;
    this.build();
    this.schedule();
  }

  Viewer.prototype.build = function () {
    var self = this;
    var ui = el('div', 'v-ui');
    var list = el('ol', 'v-list');
    list.setAttribute('aria-label', 'methods');
    this.buttons = this.items.map(function (it, i) {
      var li = el('li');
      var b = el('button', 'v-pick');
      b.type = 'button';
      var k = i + self.base;
      b.appendChild(el('kbd', '', k <= 9 ? String(k) : ' '));
      b.appendChild(el('span', 'v-name', it.label));
      if (it.figures) b.appendChild(el('span', 'v-fig', it.figures));
      b.addEventListener('click', function () { self.select(i); });
      li.appendChild(b);
      list.appendChild(li);
      return b;
    });
    var main = el('div', 'v-main');
    var bar = el('div', 'v-bar');
    this.layerButtons = {};
    this.layerNames.forEach(function (l) {
      var key = Object.keys(LAYER_KEYS).filter(function (k) { return LAYER_KEYS[k] === l; })[0];
      var caption = self.captionOf(l);
      var b = el('button', 'v-layer', key ? caption + ' (' + key + ')' : caption);
      b.type = 'button';
      b.addEventListener('click', function () { self.setLayer(l); });
      bar.appendChild(b);
      self.layerButtons[l] = b;
    });
    if (this.canOverlay) {
      this.overlayButton = el('button', 'v-toggle', '|error| over shaded (o)');
      this.overlayButton.type = 'button';
      this.overlayButton.addEventListener('click', function () { self.toggleOverlay(); });
      bar.appendChild(this.overlayButton);
    }
    var out = el('button', 'v-layer', 'zoom − (−)');
    out.type = 'button';
    out.addEventListener('click', function () { self.stepZoom(-1); });
    var into = el('button', 'v-layer', 'zoom + (+)');
    into.type = 'button';
    into.addEventListener('click', function () { self.stepZoom(1); });
    bar.appendChild(out);
    bar.appendChild(into);
    main.appendChild(bar);
    var stage = el('div', 'v-stage');
    this.img = el('img', 'v-img');
    this.img.alt = '';
    this.over = el('img', 'v-over');
    this.over.alt = '';
    this.overClip = el('div', 'v-overclip');
    this.overClip.appendChild(this.over);
    this.cropBox = el('div', 'v-crop');
    stage.appendChild(this.img);
    stage.appendChild(this.overClip);
    stage.appendChild(this.cropBox);
    stage.addEventListener('mousemove', function (e) { if (!self.locked) self.aim(e); });
    stage.addEventListener('click', function (e) { self.aim(e); self.locked = true; self.show(); });
    this.stage = stage;
    main.appendChild(stage);
    this.caption = el('p', 'v-caption');
    main.appendChild(this.caption);
    var side = el('div', 'v-side');
    this.zoomCanvas = el('canvas', 'v-zoom');
    this.zoomCanvas.width = ZOOM_PX;
    this.zoomCanvas.height = ZOOM_PX;
    side.appendChild(this.zoomCanvas);
    this.zoomCaption = el('p', 'v-zoomcap');
    side.appendChild(this.zoomCaption);
    var strip = el('div', 'v-strip');
    this.strip = this.items.map(function (it, i) {
      var f = el('figure');
      var c = el('canvas');
      c.width = STRIP_PX;
      c.height = STRIP_PX;
      c.addEventListener('click', function () { self.select(i); });
      f.appendChild(c);
      f.appendChild(el('figcaption', '', it.label));
      strip.appendChild(f);
      return { fig: f, canvas: c };
    });
    side.appendChild(strip);
    ui.appendChild(list);
    ui.appendChild(main);
    ui.appendChild(side);
    this.root.insertBefore(ui, this.root.firstChild);
    this.root.classList.add('live');
    if (!this.root.hasAttribute('tabindex')) this.root.tabIndex = 0;
    this.root.addEventListener('focusin', function () { active = self; });
    this.root.addEventListener('pointerdown', function () { active = self; });
    // Pictures are data URIs in the page: redraw (once a frame at most) as they arrive.
    this.items.forEach(function (it) {
      it.order.forEach(function (l) {
        var img = it.layers[l].img;
        if (!img.complete) img.addEventListener('load', function () { self.schedule(); });
      });
    });
    if ('IntersectionObserver' in window) {
      new IntersectionObserver(function (seen) {
        var now = seen.some(function (e) { return e.isIntersecting; });
        if (now && !self.visible) { self.visible = true; self.schedule(); }
      }).observe(this.root);
    } else {
      this.visible = true;
    }
  };

  Viewer.prototype.captionOf = function (layer) {
    if (LAYER_NAMES[layer]) return LAYER_NAMES[layer];
    for (var i = 0; i < this.items.length; i++) {
      var l = this.items[i].layers[layer];
      if (l) return l.caption.replace(/^.*: /, '');
    }
    return layer;
  };

  // The layer shown for an item: the chosen one where the item has it, else its first.
  Viewer.prototype.layerOf = function (it) {
    return it.layers[this.layer] ? this.layer : it.order[0];
  };

  Viewer.prototype.select = function (i) {
    if (i < 0 || i >= this.items.length) return;
    this.current = i;
    this.show();
  };

  Viewer.prototype.selectLabel = function (label) {
    for (var i = 0; i < this.items.length; i++) {
      if (this.items[i].label === label) { this.select(i); return true; }
    }
    return false;
  };

  Viewer.prototype.setLayer = function (l) {
    if (this.layerNames.indexOf(l) < 0) return;
    this.layer = l;
    this.show();
  };

  Viewer.prototype.toggleOverlay = function () {
    if (!this.canOverlay) return;
    this.overlay = !this.overlay;
    this.show();
  };

  Viewer.prototype.stepZoom = function (d) {
    var k = ZOOMS.indexOf(this.zoom) + d;
    if (k >= 0 && k < ZOOMS.length) this.zoom = ZOOMS[k];
    this.show();
  };

  // The displayed image's scale: integer magnification of small pictures, so pixels stay square.
  Viewer.prototype.scale = function () {
    var w = this.img.naturalWidth || 1;
    var room = Math.max(128, this.stage.parentNode.clientWidth || w);
    if (w < 384) return Math.max(1, Math.min(Math.floor(384 / w), Math.floor(room / w)));
    return Math.min(1, room / w);
  };

  Viewer.prototype.aim = function (e) {
    var r = this.img.getBoundingClientRect();
    if (!r.width) return;
    this.u = Math.min(1, Math.max(0, (e.clientX - r.left) / r.width));
    this.v = Math.min(1, Math.max(0, (e.clientY - r.top) / r.width));
    this.schedule();
  };

  Viewer.prototype.schedule = function () {
    var self = this;
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(function () { self.pending = false; self.show(); });
  };

  // The crop in source pixels of an image `w` wide whose picture is `h` high: a square of
  // ZOOM_PX / zoom pixels around (u, v), kept inside the picture.
  Viewer.prototype.crop = function (w, h) {
    var side = Math.max(1, Math.min(Math.round(ZOOM_PX / this.zoom), w, h));
    var x = Math.round(this.u * w - side / 2);
    var y = Math.round(this.v * w - side / 2);
    return { x: Math.max(0, Math.min(w - side, x)), y: Math.max(0, Math.min(h - side, y)), side: side };
  };

  // The picture's height without a legend strip: the reference's (or the first item's) aspect.
  Viewer.prototype.pictureHeight = function (w) {
    var first = this.items[0];
    var img = first.layers[first.order[0]].img;
    if (!img.naturalWidth) return w;
    return Math.round(img.naturalHeight * w / img.naturalWidth);
  };

  function drawCrop(canvas, img, c, over) {
    var g = canvas.getContext('2d');
    g.imageSmoothingEnabled = false;
    g.fillStyle = '#808080';
    g.fillRect(0, 0, canvas.width, canvas.height);
    if (!img || !img.naturalWidth) return;
    g.globalAlpha = 1;
    g.drawImage(img, c.x, c.y, c.side, c.side, 0, 0, canvas.width, canvas.height);
    if (over && over.naturalWidth) {
      g.globalAlpha = 0.6;
      g.drawImage(over, c.x, c.y, c.side, c.side, 0, 0, canvas.width, canvas.height);
      g.globalAlpha = 1;
    }
  }

  Viewer.prototype.show = function () {
    var self = this;
    var it = this.items[this.current];
    if (!it) return;
    var layer = this.layerOf(it);
    var shown = it.layers[layer].img;
    if (this.img.src !== shown.src) this.img.src = shown.src;
    var overlay = this.overlay && layer === 'shaded' && it.layers.abs_error;
    var over = overlay ? it.layers.abs_error.img : null;
    if (over && this.over.src !== over.src) this.over.src = over.src;
    this.overClip.hidden = !over;
    var w = shown.naturalWidth || 1;
    var s = this.scale();
    var dw = Math.round(w * s);
    this.img.style.width = dw + 'px';
    this.img.classList.toggle('pixelated', s >= 1);
    var ph = this.pictureHeight(w);
    this.over.style.width = dw + 'px';
    this.overClip.style.width = dw + 'px';
    this.overClip.style.height = Math.round(ph * s) + 'px';
    var c = this.crop(w, ph);
    this.cropBox.style.left = c.x * s + 'px';
    this.cropBox.style.top = c.y * s + 'px';
    this.cropBox.style.width = c.side * s + 'px';
    this.cropBox.style.height = c.side * s + 'px';
    this.cropBox.classList.toggle('locked', this.locked);
    if (this.visible) drawCrop(this.zoomCanvas, shown, c, over);
    this.items.forEach(function (other, i) {
      var l = self.layerOf(other);
      var o = self.overlay && l === 'shaded' && other.layers.abs_error ? other.layers.abs_error.img : null;
      if (self.visible) drawCrop(self.strip[i].canvas, other.layers[l].img, c, o);
      self.strip[i].fig.classList.toggle('on', i === self.current);
      self.buttons[i].classList.toggle('on', i === self.current);
      self.buttons[i].setAttribute('aria-pressed', String(i === self.current));
    });
    this.layerNames.forEach(function (l) { self.layerButtons[l].classList.toggle('on', l === self.layer); });
    if (this.overlayButton) this.overlayButton.classList.toggle('on', this.overlay);
    this.caption.textContent = it.label + ' · ' + it.layers[layer].caption.replace(/^.*: /, '') + (over ? ' with |error| over it' : '') + (it.figures ? ' · ' + it.figures : '');
    this.zoomCaption.textContent = this.zoom + '× · x ' + c.x + '–' + (c.x + c.side - 1) + ', y ' + c.y + '–' + (c.y + c.side - 1) + (this.locked ? ' (click to move, Esc to follow the mouse)' : ' (click to fix)');
    // What is on screen, for a reader's script or a test: the item, layer and crop.
    this.root.dataset.current = it.label;
    this.root.dataset.layer = layer;
    this.root.dataset.overlay = over ? 'on' : 'off';
    this.root.dataset.crop = [c.x, c.y, c.side, this.zoom].join(',');
  };

  Viewer.prototype.key = function (e) {
    var k = e.key;
    if (/^[0-9]$/.test(k)) {
      var i = Number(k) - this.base;
      if (i < 0 || i >= this.items.length) return false;
      this.select(i);
    } else if (k === 'ArrowRight' || k === ']') {
      this.select((this.current + 1) % this.items.length);
    } else if (k === 'ArrowLeft' || k === '[') {
      this.select((this.current + this.items.length - 1) % this.items.length);
    } else if (LAYER_KEYS[k] && this.layerNames.indexOf(LAYER_KEYS[k]) >= 0) {
      this.setLayer(LAYER_KEYS[k]);
    } else if (k === 'l') {
      this.setLayer(this.layerNames[(this.layerNames.indexOf(this.layer) + 1) % this.layerNames.length]);
    } else if (k === 'o' && this.canOverlay) {
      this.toggleOverlay();
    } else if (k === '+' || k === '=') {
      this.stepZoom(1);
    } else if (k === '-') {
      this.stepZoom(-1);
    } else if (k === 'Escape' && this.locked) {
      this.locked = false;
      this.show();
    } else {
      return false;
    }
    return true;
  };

  // Keys go to the viewer last clicked or focused, else to the one most in view.
  function target() {
    if (active) return active;
    var best = null;
    var seen = 0;
    viewers.forEach(function (v) {
      var r = v.root.getBoundingClientRect();
      var h = Math.min(r.bottom, innerHeight) - Math.max(r.top, 0);
      if (h > seen) { seen = h; best = v; }
    });
    return best;
  }

  function viewerFor(scene, label) {
    for (var i = 0; i < viewers.length; i++) {
      var v = viewers[i];
      if ((!scene || v.root.dataset.scene === scene) && v.items.some(function (it) { return it.label === label; })) return v;
    }
    return null;
  }

  // Chart points: `.hit` marks carry the row's label, scene and figures (their <title> is the
  // tooltip without a script); here they get a tooltip on hover and focus, and open the method.
  function charts() {
    var tip = el('div', 'v-tip');
    tip.hidden = true;
    document.body.appendChild(tip);
    document.querySelectorAll('svg .hit').forEach(function (p) {
      var title = p.querySelector('title');
      var text = title ? title.textContent : p.getAttribute('aria-label') || '';
      var place = function () {
        var r = p.getBoundingClientRect();
        tip.textContent = text;
        tip.hidden = false;
        tip.style.left = (scrollX + r.right + 8) + 'px';
        tip.style.top = (scrollY + r.top - 4) + 'px';
      };
      var open = function () {
        var v = viewerFor(p.dataset.scene, p.dataset.label);
        if (!v) return;
        v.selectLabel(p.dataset.label);
        active = v;
        v.root.scrollIntoView({ block: 'start' });
        v.root.focus({ preventScroll: true });
      };
      p.addEventListener('mouseenter', place);
      p.addEventListener('focus', place);
      p.addEventListener('mouseleave', function () { tip.hidden = true; });
      p.addEventListener('blur', function () { tip.hidden = true; });
      p.addEventListener('click', open);
      p.addEventListener('keydown', function (e) {
        if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); open(); }
      });
    });
  }

  function init() {
    document.querySelectorAll('.viewer').forEach(function (root) {
      if (root.querySelector(':scope > .v-item')) viewers.push(new Viewer(root));
    });
    charts();
    document.addEventListener('keydown', function (e) {
      if (e.ctrlKey || e.metaKey || e.altKey) return;
      if (e.target && /^(INPUT|TEXTAREA|SELECT)$/.test(e.target.tagName)) return;
      var v = target();
      if (v && v.key(e)) e.preventDefault();
    });
    window.addEventListener('resize', function () { viewers.forEach(function (v) { v.schedule(); }); });
    document.documentElement.dataset.viewers = String(viewers.length);
  }

  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', init);
  else init();
})();
