// Installed first: a script error or console.error marks the page (title and an attribute),
// which a test reads back from the DOM.
(function(){
  function mark(m){document.title='JS-ERROR: '+m;document.documentElement.setAttribute('data-js-error',String(m));}
  window.onerror=function(m,s,l){mark(m+' (line '+l+')');};
  window.addEventListener('unhandledrejection',function(e){mark('unhandled rejection: '+e.reason);});
  var ce=console.error;console.error=function(){mark('console.error: '+Array.prototype.join.call(arguments,' '));ce.apply(console,arguments);};
})();
