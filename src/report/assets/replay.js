// The replay: a trial's frames with the measured and the simulated markers and their magnified
// residuals drawn over them. Glyphs, colours and the magnification come from the page's replay
// JSON (src/report/replay_html.cc writes them from src/compare/replay_convention.h, which the
// overlay video draws from too).
(function(){
  var data=JSON.parse(document.getElementById('replay-data').textContent);
  if(!data.trials.length) return;
  var sel=document.getElementById('replay-trial'),slider=document.getElementById('replay-frame'),
      ov=document.getElementById('replay-overlay'),canvas=document.getElementById('replay-canvas'),
      info=document.getElementById('replay-info'),ctx=canvas.getContext('2d'),cur=0,
      G=data.glyphs,R=data.marker_radius,F=data.residual_scale;
  data.trials.forEach(function(r,i){var o=document.createElement('option');o.value=String(i);
    o.textContent=r.id+' ('+r.surface+')';sel.appendChild(o);});
  function ok(p){return p[0]!==null&&p[1]!==null;}
  // One glyph g at (x, y) on the canvas; an arrow goes to (x2, y2).
  function glyph(g,x,y,x2,y2){
    ctx.strokeStyle=g.colour;ctx.beginPath();
    var s=g.size*R;
    if(g.shape==='ring'){ctx.arc(x,y,s,0,2*Math.PI);}
    else if(g.shape==='plus'){ctx.moveTo(x-s,y);ctx.lineTo(x+s,y);ctx.moveTo(x,y-s);ctx.lineTo(x,y+s);}
    else if(g.shape==='arrow'){
      var dx=x2-x,dy=y2-y,l=Math.sqrt(dx*dx+dy*dy);
      if(l<0.5)return;
      ctx.moveTo(x,y);ctx.lineTo(x2,y2);
      var h=Math.min(s,l/2),ux=dx/l,uy=dy/l;
      ctx.moveTo(x2-h*(ux-0.5*uy),y2-h*(uy+0.5*ux));ctx.lineTo(x2,y2);
      ctx.lineTo(x2-h*(ux+0.5*uy),y2-h*(uy-0.5*ux));
    }
    ctx.stroke();
  }
  function draw(){
    var r=data.trials[cur],k=Number(slider.value),f=r.frames[k],im=document.getElementById('f'+cur+'_'+k),z=1.5;
    canvas.width=Math.round(im.naturalWidth*z);canvas.height=Math.round(im.naturalHeight*z);
    ctx.drawImage(im,0,0,canvas.width,canvas.height);
    if(ov.checked){
      var s=r.scale*z;ctx.lineWidth=2;
      // A ball: its simulated circle about the simulated centre, in the simulated colour.
      if(r.ball_radius_px!==null&&f.sim.length&&ok(f.sim[0])){ctx.strokeStyle=G.simulated.colour;
        ctx.beginPath();ctx.arc(f.sim[0][0]*s,f.sim[0][1]*s,r.ball_radius_px*s,0,2*Math.PI);ctx.stroke();}
      f.sim.forEach(function(p){if(ok(p))glyph(G.simulated,p[0]*s,p[1]*s);});
      f.meas.forEach(function(p){if(ok(p))glyph(G.measured,p[0]*s,p[1]*s);});
      // measured -> measured + F (simulated - measured), in image px, then to the canvas.
      f.meas.forEach(function(p,m){var q=f.sim[m];if(!ok(p)||!q||!ok(q))return;
        glyph(G.residual,p[0]*s,p[1]*s,(p[0]+F*(q[0]-p[0]))*s,(p[1]+F*(q[1]-p[1]))*s);});
    }
    var d=f.frame-r.impact;
    info.textContent='frame '+f.frame+' ('+(d>=0?'+':'')+d+' from impact), t = '+f.t_text+
      ', largest residual '+f.residual_text+' (arrows '+F+'\u00d7)';
    canvas.setAttribute('data-drawn-frame',String(f.frame));
    // Where the canvas is on the page (px), for the tests that look at a screenshot.
    var b=canvas.getBoundingClientRect();
    canvas.setAttribute('data-rect',[b.left+window.scrollX,b.top+window.scrollY,b.width,b.height].map(Math.round).join(','));
    document.body.setAttribute('data-replay-drawn',r.id);
  }
  function select(i){cur=i;var r=data.trials[i];slider.max=String(r.frames.length-1);
    var k=0;r.frames.forEach(function(f,j){if(f.frame<=r.impact)k=j;});slider.value=String(k);draw();}
  function step(d){slider.value=String(Math.min(Number(slider.max),Math.max(0,Number(slider.value)+d)));draw();}
  sel.addEventListener('change',function(){select(Number(sel.value));});
  slider.addEventListener('input',draw);ov.addEventListener('change',draw);
  document.getElementById('replay-prev').addEventListener('click',function(){step(-1);});
  document.getElementById('replay-next').addEventListener('click',function(){step(1);});
  document.addEventListener('keydown',function(e){if(e.key==='ArrowLeft')step(-1);if(e.key==='ArrowRight')step(1);});
  if(location.hash.indexOf('overlay=off')>=0)ov.checked=false;
  if(document.readyState==='complete')select(0);else window.addEventListener('load',function(){select(0);});
})();
