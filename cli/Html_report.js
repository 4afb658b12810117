// The HTML report's script (cli/Html_report.cpp inlines it after three.js r111, OrbitControls
// and GLTFLoader): selects a pair from the summary table and shows it, at its worst moment, in
// the 3D view, with its row and its plot beside it.
//
// The page's data: #report-data (JSON: per scene pair its bodies, class, worst moment, the
// poses of its bodies there as column-major 4x4 matrices in scene units, its witness points)
// and #view-data (base64 binary glTF of the watched bodies in their body frames, nodes named
// body<i> after the scene's bodies, under a root node mapping scene units, z up, to glTF's
// metres, y up). When the first pair is drawn, <html> gets data-view="drawn", data-ready-ms (the
// time since the page started loading) and data-canvas (the canvas's box in page pixels);
// data-selected is the selected pair's index in the scene.
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('report-data').textContent);
  var canvas = document.getElementById('view');
  var caption = document.getElementById('view-caption');
  var note = document.getElementById('view-note');
  var rows = Array.prototype.slice.call(document.querySelectorAll('#summary tbody tr'));
  var headers = Array.prototype.slice.call(document.querySelectorAll('#summary thead th'))
      .map(function (th) { return th.textContent; });
  var root = document.documentElement;

  var colourA = 0x3b7dd8, colourB = 0xe8913a, witnessColour = 0xd62728;
  var background = 0xeef1f5;  // #view-box's background in the style sheet
  var renderer = null, camera = null, scene = null, controls = null, frame = null;
  var nodes = {};  // scene body index -> its node in the glTF
  var marks = null;  // the witness segment and its end points
  var selected = -1, drawn = false;

  function escapeText(text) {
    var div = document.createElement('div');
    div.textContent = text;
    return div.innerHTML;
  }

  function showNote(text) {
    note.hidden = !text;
    note.textContent = text || '';
  }

  function render() {
    if (renderer && scene && camera) renderer.render(scene, camera);
  }

  function resize() {
    if (!renderer) return;
    var w = Math.max(1, canvas.clientWidth), h = Math.max(1, canvas.clientHeight);
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  }

  function showRow(k) {
    var pair = data.pairs[k];
    document.getElementById('pair-title').textContent = pair.name;
    var row = document.querySelector('#summary tbody tr[data-pair="' + k + '"]');
    var table = document.getElementById('pair-row');
    table.innerHTML = '';
    Array.prototype.forEach.call(row.cells, function (cell, i) {
      if (i < 2) return;  // the number and the name are in the title
      var tr = table.insertRow();
      var th = document.createElement('th');
      th.textContent = headers[i];
      tr.appendChild(th);
      tr.insertCell().innerHTML = cell.innerHTML;
    });
    var tr = table.insertRow();
    var th = document.createElement('th');
    th.textContent = '3D view at t (s)';
    tr.appendChild(th);
    tr.insertCell().textContent = pair.t + ' (distance ' + pair.distance.toPrecision(6) + ', ' +
        pair.status + ')';
    var plot = document.getElementById('pair-plot');
    plot.innerHTML = '';
    plot.appendChild(document.getElementById('plot-' + k).content.cloneNode(true));
    rows.forEach(function (r) { r.classList.toggle('selected', +r.dataset.pair === k); });
  }

  function material(colour) {
    return new THREE.MeshPhongMaterial({color: colour, side: THREE.DoubleSide, shininess: 30});
  }

  function showPair(k) {
    var pair = data.pairs[k];
    Object.keys(nodes).forEach(function (i) { nodes[i].visible = false; });
    if (marks) {
      scene.remove(marks);
      marks = null;
    }
    if (!pair.in_view) {
      caption.innerHTML = '';
      showNote('The 3D data of this pair is not in the page: its bodies would have made it too ' +
               'large (extremal report --snapshot writes any moment as glTF).');
      render();
      return;
    }
    showNote('');
    [[pair.a, pair.pose_a, colourA], [pair.b, pair.pose_b, colourB]].forEach(function (p) {
      var node = nodes[p[0]];
      node.visible = true;
      node.matrix.fromArray(p[1]);
      var m = material(p[2]);
      node.traverse(function (o) { if (o.isMesh) o.material = m; });
    });
    frame.updateMatrixWorld(true);
    var boxA = new THREE.Box3().setFromObject(nodes[pair.a]);
    var boxB = new THREE.Box3().setFromObject(nodes[pair.b]);
    var ends = [];
    if (pair.witness) {
      ends = pair.witness.map(function (p) {
        return frame.localToWorld(new THREE.Vector3(p[0], p[1], p[2]));
      });
    }
    // The view holds both bodies, or, when one is far larger, the smaller one and the witness
    // with some of the larger around them (zoom out for the rest).
    var small = boxA.getSize(new THREE.Vector3()).length() <=
                boxB.getSize(new THREE.Vector3()).length() ? boxA.clone() : boxB.clone();
    var both = boxA.clone().union(boxB);
    ends.forEach(function (v) { small.expandByPoint(v); both.expandByPoint(v); });
    var target = new THREE.Vector3();
    if (ends.length) target.addVectors(ends[0], ends[1]).multiplyScalar(0.5);
    else small.getCenter(target);
    function reach(box) {  // the radius about the target of a sphere holding the box
      var sphere = new THREE.Sphere();
      box.getBoundingSphere(sphere);
      return sphere.radius + target.distanceTo(sphere.center);
    }
    var radius = Math.max(Math.min(reach(both), 3 * reach(small)), 1e-9);
    marks = new THREE.Group();
    if (ends.length) {
      var red = new THREE.LineBasicMaterial({color: witnessColour});
      marks.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(ends), red));
      var dot = new THREE.SphereBufferGeometry(0.012 * radius, 16, 12);
      var dotMaterial = new THREE.MeshBasicMaterial({color: witnessColour});
      ends.forEach(function (v) {
        var s = new THREE.Mesh(dot, dotMaterial);
        s.position.copy(v);
        marks.add(s);
      });
    }
    scene.add(marks);  // in world coordinates
    // Far enough that the sphere about the target holding both bodies fills the view.
    var direction = new THREE.Vector3(1, 0.8, 1.3).normalize();
    var halfAngle = Math.PI / 360 * Math.min(camera.fov, camera.fov * camera.aspect);
    var distance = 0.9 * radius / Math.sin(halfAngle);
    camera.near = distance / 1000;
    camera.far = distance * 10;
    camera.position.copy(target).addScaledVector(direction, distance);
    camera.updateProjectionMatrix();
    controls.target.copy(target);
    controls.update();
    caption.innerHTML = '<span class="a">' + escapeText(data.bodies[pair.a]) + '</span> and ' +
        '<span class="b">' + escapeText(data.bodies[pair.b]) + '</span> at t = ' + pair.t +
        ' s' + (pair.witness ? ', <span class="w">witness segment</span>' : ' (farther than ' +
        'the threshold throughout: no witness)');
    render();
  }

  function select(k) {
    if (k === selected || !data.pairs[k]) return;
    selected = k;
    showRow(k);
    if (frame) showPair(k);
    root.setAttribute('data-selected', String(k));
  }

  function markDrawn() {
    if (drawn) return;
    drawn = true;
    var r = canvas.getBoundingClientRect();
    root.setAttribute('data-canvas', [Math.round(r.left + window.scrollX),
        Math.round(r.top + window.scrollY), Math.round(r.width), Math.round(r.height)].join(','));
    root.setAttribute('data-ready-ms', String(Math.round(performance.now())));
    root.setAttribute('data-view', 'drawn');
  }

  function startView(gltf) {
    var group = gltf.scene;
    scene.add(group);
    group.updateMatrixWorld(true);
    Object.keys(data.pairs).forEach(function (k) {
      var pair = data.pairs[k];
      if (!pair.in_view) return;
      [pair.a, pair.b].forEach(function (i) {
        if (nodes[i]) return;
        var node = group.getObjectByName('body' + i);
        if (!node) throw new Error('the 3D data has no body ' + i + ' (' + data.bodies[i] + ')');
        node.matrixAutoUpdate = false;
        node.visible = false;
        nodes[i] = node;
      });
    });
    var any = nodes[Object.keys(nodes)[0]];
    frame = any ? any.parent : group;
    var k = selected;
    selected = -1;
    select(k);
    markDrawn();
  }

  rows.forEach(function (r) {
    var k = +r.dataset.pair;
    r.addEventListener('click', function () { select(k); });
    r.addEventListener('keydown', function (e) { if (e.key === 'Enter') select(k); });
  });
  if (data.worst < 0) return;
  select(data.worst);

  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true,
                                        preserveDrawingBuffer: true});
  } catch (e) {
    showNote('No 3D view: this browser could not start WebGL (' + e.message + ').');
    root.setAttribute('data-view', 'no-webgl');
    return;
  }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  scene = new THREE.Scene();
  scene.background = new THREE.Color(background);
  camera = new THREE.PerspectiveCamera(35, 1, 0.001, 1000);
  scene.add(camera);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x555555, 0.75));
  var light = new THREE.DirectionalLight(0xffffff, 0.6);
  light.position.set(0.5, 1, 1);
  camera.add(light);  // the light turns with the view
  controls = new THREE.OrbitControls(camera, canvas);
  controls.addEventListener('change', render);
  window.addEventListener('resize', resize);
  resize();

  var text = atob(document.getElementById('view-data').textContent.trim());
  var bytes = new Uint8Array(text.length);
  for (var i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
  new THREE.GLTFLoader().parse(bytes.buffer, '', startView, function (e) {
    console.error('the 3D data could not be read: ' + (e && e.message ? e.message : e));
  });
})();
