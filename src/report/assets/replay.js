// The replay: a trial's frames with the measured and the simulated specimen drawn over them.
(function(){
  var data=JSON.parse(document.getElementById('replay-data').textContent);
  if(!data.length) return;
  var sel=document.getElementById('replay-trial'),slider=document.getElementById('replay-frame'),
      ov=document.getElementById('replay-overlay'),canvas=document.getElementById('replay-canvas'),
      info=document.getElementById('replay-info'),ctx=canvas.getContext('2d'),cur=0;
  data.forEach(function(r,i){var o=document.createElement('option');o.value=String(i);
    o.textContent=r.id+' ('+r.surface+')';sel.appendChild(o);});
  function ok(p){return p[0]!==null&&p[1]!==null;}
  function draw(){
    var r=data[cur],k=Number(slider.value),f=r.frames[k],im=document.getElementById('f'+cur+'_'+k),z=1.5;
    canvas.width=Math.round(im.naturalWidth*z);canvas.height=Math.round(im.naturalHeight*z);
    ctx.drawImage(im,0,0,canvas.width,canvas.height);
    if(ov.checked){
      var s=r.scale*z;ctx.lineWidth=2;
      ctx.strokeStyle='#00e676';
      f.meas.forEach(function(p){if(!ok(p))return;ctx.beginPath();ctx.arc(p[0]*s,p[1]*s,7,0,2*Math.PI);ctx.stroke();});
      ctx.strokeStyle='#ff2d95';
      f.sim.forEach(function(p){if(!ok(p))return;var x=p[0]*s,y=p[1]*s;ctx.beginPath();
        ctx.moveTo(x-8,y);ctx.lineTo(x+8,y);ctx.moveTo(x,y-8);ctx.lineTo(x,y+8);ctx.stroke();});
    }
    var d=f.frame-r.impact;
    info.textContent='frame '+f.frame+' ('+(d>=0?'+':'')+d+' from impact), t = '+
      (f.t_ms===null?'?':f.t_ms.toFixed(3))+' ms';
    canvas.setAttribute('data-drawn-frame',String(f.frame));
    document.body.setAttribute('data-replay-drawn',r.id);
  }
  function select(i){cur=i;var r=data[i];slider.max=String(r.frames.length-1);
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
